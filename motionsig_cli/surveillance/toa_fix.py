"""Snapshot position and clock fix from times of arrival (TOA) at several receivers: weighted least squares by
Gauss–Newton, vectorised over epochs (ATC-10, Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972:
§4.2, eqs 4.2.1–4.2.3 and 4.5.1–4.5.4, here with the receivers' own weights and an unknown number of them).

**Model.** A transmitter at p sends a pulse at τ; receiver i at S_i (clocks synchronised on the ground)
records it at T_i = τ + ‖p − S_i‖/c + ε_i (eq 4.2.1). With the epoch's nominal time t, the pseudorange is

    ρ_i = c (T_i − t) = ‖p − S_i‖ + b + c ε_i,   b = c (τ − t),

so the unknowns are x = (p, b) [m]: the position and the clock offset b/c = τ − t (the emission time minus
the epoch's nominal time). Linearised at x*, ρ − ‖p* − S‖ − b* = H (x − x*) + cε with the rows of
H = [u_i' 1], u_i = (p* − S_i)/‖p* − S_i‖ the unit vector from receiver i to the transmitter (eq 4.2.3:
F = U/c, and the clock column 1 of eq 4.5.1).

**Solution.** Weights W = diag(1/σ_i²); each Gauss–Newton step is the least-squares solution of the
whitened system W^½ H Δx = W^½ r by a thin QR factorisation (never the normal equations), halved while it
would increase χ² (a backtracking line search), vectorised over the epochs: a receiver absent at an epoch
has weight zero. It stops when the step is below ``tol`` (default
1 µm), or when the χ² decrease it promises is below what can be resolved (the rounding of the residuals,
or 10⁻¹⁴ of χ²: an ill-conditioned geometry magnifies rounding into longer steps), or after ``max_iter`` steps (the epoch is then flagged as
not converged, and may be restarted from a neighbouring epoch's fix). For a ground network, whose receivers lie nearly in one plane, the problem has
a second minimum near the mirror image of the transmitter in that plane, which fits about as well (the
data hardly tell them apart: measured χ² differences of 0.1 to 3 for a 30 km network and a transmitter 2 to
5 km up) and which Gauss–Newton reaches from some starting points. For such a network (flatness below
:data:`FLAT_RATIO`) the solver also starts from the mirror image of its fix and keeps the minimum on the
starting point's side of the plane: the default start, the closed-form solution above the plane
(:mod:`~motionsig_cli.surveillance.bancroft`; both of Bancroft's roots are refined for other geometries,
and where the closed form fails the start is :data:`START_ALT_M` above the receivers' centroid), says
"above the receivers" (assumed); a transmitter below them needs a starting point below. The covariance of x̂ is
(HᵀWH)⁻¹ = R⁻¹R⁻ᵀ at the solution, unscaled when the σ_i are known (``scale="none"``), or multiplied by the
a-posteriori variance factor s² = rᵀWr/(K − 4) of each epoch (``"epoch"``) or of all epochs pooled
(``"pooled"``: Σ rᵀWr / Σ (K − 4)) when they are relative weights only.

**Dilution of precision** (unweighted H at the solution; (HᵀH)⁻¹ = G): GDOP = √tr G,
PDOP = √(G_xx + G_yy + G_zz), TDOP = √G_bb, and HDOP, VDOP in the local east-north-up frame of the fix
(WGS-84). The report's "GDOP" k = √(tr + b/β) (eq 4.1.2) is the PDOP here (its clock column is the ones
vector, in c = 1 units).

**Geometry.** A fix needs at least four receivers; a geometry whose H has a condition number above
:data:`~motionsig_cli.surveillance.multilateration.COND_LIMIT` (e.g. all receivers on a line, or the clock
column in the span of the directions) is refused with a :class:`SingularGeometry` naming the epoch, or
(``on_failure="flag"``) that epoch alone has no fix and a ``status`` saying why. A receiver absent at an
epoch (NaN pseudorange or position) is left out of that epoch's algebra.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of, positive
from motionsig_cli.geodesy import covariance_to_enu, ecef_to_geodetic, surface_point
from motionsig_cli.surveillance.multilateration import COND_LIMIT, GeometryError, solve_upper, thin_qr

__all__ = [
    "C_M_PER_S",
    "MIN_RECEIVERS",
    "NO_FIX",
    "SCALES",
    "START_ALT_M",
    "EpochError",
    "SingularGeometry",
    "SnapshotFix",
    "WeightedPseudo",
    "default_start",
    "position_covariance",
    "receiver_plane",
    "scale_covariance",
    "solve_snapshot",
    "weighted_position_update",
    "weighted_pseudo_measurement",
]

C_M_PER_S = 299_792_458.0
"""Speed of light in vacuum [m/s], exact (the propagation medium is not modelled: assumed)."""
MIN_RECEIVERS = 4
"""Fewest receivers for a snapshot fix of position and clock."""
SCALES = ("none", "epoch", "pooled")
NO_FIX = ("too few receivers", "singular geometry", "no convergence")
"""Why an epoch has no fix (:attr:`SnapshotFix.status`)."""
"""Covariance scaling: none (σ known), by each epoch's variance factor, by the pooled variance factor."""
START_ALT_M = 10_000.0
"""Height of the default starting point above the ellipsoid [m] (assumed): above a ground network, so that
Gauss–Newton reaches the solution above the receivers' plane and not its mirror image below it."""


FLAT_RATIO = 0.1
"""Receivers whose positions' smallest singular value (about their centroid) is below this fraction of the
largest are "nearly in one plane" (a ground network; assumed): the fix's mirror image in that plane is a
second candidate minimum."""
EPS = float(np.finfo(float).eps)
CHI2_RTOL = 1e-14
ACCEPT_RTOL = 1e-13
"""A step is accepted by the line search while χ² grows by less than this fraction, or than its rounding
(:func:`_chi2_rounding`)."""
GN_STEPS = 8
"""Gauss–Newton steps before an epoch that has not converged goes on with Newton's (up to ``max_iter`` in
all): near a solution Gauss–Newton converges in a few steps, and where it crawls Newton's steps are quadratic."""
"""Relative χ² changes below this are not resolved: the line search accepts them, and a step that promises
less has converged."""
MAX_HALVINGS = 40
"""Most halvings of a Gauss–Newton step in the line search (2⁻⁴⁰ ≈ 10⁻¹²)."""
DIVERGED_M = 1e10
"""A Gauss–Newton step that takes the position further than this from the Earth's centre [m] has diverged
(the epoch stops there, not converged)."""


class EpochError(ValueError):
    """A failure at one epoch of a record, ``epoch {epoch}: {reason}``.

    Attributes:
        epoch: the index of the epoch.
        reason: what is wrong.
    """

    def __init__(self, epoch: int, reason: str) -> None:
        self.epoch = int(epoch)
        self.reason = reason
        super().__init__(f"epoch {epoch}: {reason}")


class SingularGeometry(EpochError, GeometryError):
    """A geometry that cannot fix position and clock at one epoch (``epoch``: its index in the arrays given
    to :func:`solve_snapshot`)."""


@dataclass(frozen=True)
class SnapshotFix:
    """Per-epoch least-squares fixes (arrays over E epochs and K receiver slots).

    Attributes:
        position: (E, 3) ECEF position [m].
        bias: (E,) b = c(τ − t) [m]; the clock offset τ − t is ``bias / C_M_PER_S``.
        covariance: (E, 4, 4) covariance of (x, y, z, b) [m²] (scaled as ``scale`` says).
        gdop, pdop, hdop, vdop, tdop: (E,) dilutions of precision (unweighted geometry).
        residuals: (E, K) ρ − ‖p̂ − S‖ − b̂ [m] (NaN where a receiver is absent).
        normalised: (E, K) residuals / σ.
        rms_residual: (E,) root-mean-square residual over the receivers used [m].
        chi2: (E,) Σ (residual/σ)².
        variance_factor: (E,) the factor applied to the covariance (1 for ``scale="none"``).
        n_used: (E,) receivers used.
        iterations: (E,) Gauss–Newton steps taken.
        converged: (E,) the last step was below the tolerance.
        retried: (E,) the epoch was restarted from a neighbour's fix (``retry``).
        mirrored: (E,) the solution came from the mirror-image start (``mirror``): the first minimum found
            was on the other side of the receivers' plane from the starting point.
        other_chi2: (E,) χ² of the other (mirror-image) minimum, NaN where none was found or looked for.
        cond: (E,) condition number of the unweighted H at the solution.
        scale: the covariance scaling (one of :data:`SCALES`).
        status: (E,) why an epoch has no fix (``""``: it has one): ``"too few receivers"``, ``"singular
            geometry"`` or ``"no convergence"`` (with ``on_failure="flag"``; see :data:`NO_FIX`).
        started: (E,) where Gauss–Newton started: ``"closed form"`` (Bancroft), ``"given"`` or
            ``"centroid"`` (the closed form failed).
    """

    position: np.ndarray
    bias: np.ndarray
    covariance: np.ndarray
    gdop: np.ndarray
    pdop: np.ndarray
    hdop: np.ndarray
    vdop: np.ndarray
    tdop: np.ndarray
    residuals: np.ndarray
    normalised: np.ndarray
    rms_residual: np.ndarray
    chi2: np.ndarray
    variance_factor: np.ndarray
    n_used: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    retried: np.ndarray
    mirrored: np.ndarray
    other_chi2: np.ndarray
    cond: np.ndarray
    scale: str
    status: np.ndarray | None = None
    started: np.ndarray | None = None

    @property
    def ok(self) -> np.ndarray:
        """(E,) epochs with a fix (converged, no failure)."""
        return self.converged & (self.status == "") if self.status is not None else self.converged

    @property
    def clock_offset_s(self) -> np.ndarray:
        """τ − t [s]: the emission time minus the epoch's nominal time."""
        return self.bias / C_M_PER_S

    @property
    def sd(self) -> np.ndarray:
        """(E, 4) standard deviations of x, y, z, b [m]."""
        return np.sqrt(np.maximum(np.diagonal(self.covariance, axis1=-2, axis2=-1), 0.0))

    def sd_enu(self) -> np.ndarray:
        """(E, 3) standard deviations of the position east, north, up [m] at the fix."""
        lat, lon, _ = ecef_to_geodetic(self.position, strict=False)
        P = covariance_to_enu(self.covariance[:, :3, :3], lat, lon)
        return np.sqrt(np.maximum(np.diagonal(P, axis1=-2, axis2=-1), 0.0))


def _broadcast(receivers: np.ndarray, E: int, K: int) -> np.ndarray:
    S = np.asarray(receivers, dtype=float)
    if S.shape == (K, 3):
        S = np.broadcast_to(S, (E, K, 3))
    if S.shape != (E, K, 3):
        raise ValueError(f"receivers must be (K, 3) or (E, K, 3) = ({E}, {K}, 3), got {S.shape}")
    return S


def default_start(receivers: np.ndarray, used: np.ndarray, alt_m: float = START_ALT_M) -> np.ndarray:
    """The starting point of each epoch: the centroid of the receivers used, pushed along the ellipsoid's
    normal to ``alt_m`` above it (:func:`~motionsig_cli.geodesy.surface_point`)."""
    w = used.astype(float)[..., None]
    c = np.sum(np.where(w > 0, receivers, 0.0), axis=-2) / np.maximum(np.sum(w, axis=-2), 1.0)
    return surface_point(c, alt_m)


def _qr_step(
    S: np.ndarray, rho: np.ndarray, w: np.ndarray, p: np.ndarray, b: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One Gauss–Newton step at (p, b): returns (step (n, 4), R (n, 4, 4), residual r (n, K), U (n, K, 3))."""
    d = p[:, None, :] - S
    rng = np.linalg.norm(d, axis=-1)
    U = d / np.where(rng > 0, rng, 1.0)[..., None]
    r = np.where(w > 0, rho - rng - b[:, None], 0.0)
    A = np.concatenate([U, np.ones((*U.shape[:-1], 1))], axis=-1) * w[..., None]  # W^½ [U 1]
    Q, R = thin_qr(A)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = solve_upper(R, np.einsum("...kj,...k->...j", Q, r * w))
    return step, R, r, U


def _cond(U: np.ndarray, used: np.ndarray) -> np.ndarray:
    """Condition number of the unweighted H = [U 1] (rows of absent receivers zero), per epoch."""
    H = np.concatenate([U, np.ones((*U.shape[:-1], 1))], axis=-1) * used[..., None]
    sv = np.linalg.svd(H, compute_uv=False)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(sv[..., -1] > 0, sv[..., 0] / sv[..., -1], np.inf)


def _mean_bias(S: np.ndarray, rho0: np.ndarray, w: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The clock offset b that fits best at the position p: the weighted mean of ρ − ‖p − S‖."""
    rng = np.linalg.norm(p[:, None, :] - S, axis=-1)
    w2 = w**2
    return np.sum(w2 * (rho0 - rng), axis=1) / np.sum(w2, axis=1)


def _chi2_rounding(
    S: np.ndarray, rho0: np.ndarray, w: np.ndarray, p: np.ndarray, b: np.ndarray
) -> np.ndarray:
    """How much χ² can move by rounding alone (10 × Σ 2|z_i| w_i ε (|ρ_i| + ‖S_i‖ + ‖p‖), plus 10⁻¹² and
    :data:`ACCEPT_RTOL` χ²): the line search does not tell apart χ² values closer than this."""
    z = (rho0 - np.linalg.norm(p[:, None, :] - S, axis=-1) - b[:, None]) * w
    scale = (
        np.abs(rho0) + np.linalg.norm(S, axis=-1) + np.linalg.norm(p, axis=-1)[:, None] + np.abs(b)[:, None]
    )
    return (
        10.0 * np.sum(2.0 * np.abs(z) * w * EPS * scale, axis=1) + ACCEPT_RTOL * np.sum(z * z, axis=1) + 1e-12
    )


def _chi2(S: np.ndarray, rho0: np.ndarray, w: np.ndarray, p: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Σ ((ρ − ‖p − S‖ − b)/σ)² per epoch."""
    r = (rho0 - np.linalg.norm(p[:, None, :] - S, axis=-1) - b[:, None]) * w
    return np.sum(r * r, axis=1)


def receiver_plane(receivers: np.ndarray, used: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The best-fitting plane of each epoch's receivers: centroid (E, 3), unit normal (E, 3) and flatness
    (E,), the smallest over the largest singular value of the centred positions (0: coplanar)."""
    wt = used.astype(float)[..., None]
    centre = np.sum(np.where(wt > 0, receivers, 0.0), axis=-2) / np.maximum(np.sum(wt, axis=-2), 1.0)
    d = np.where(wt > 0, receivers - centre[:, None, :], 0.0)
    _, sv, vt = np.linalg.svd(d, full_matrices=False)
    with np.errstate(divide="ignore", invalid="ignore"):
        flat = np.where(sv[:, 0] > 0, sv[:, -1] / sv[:, 0], 1.0)
    return centre, vt[:, -1, :], flat


def _gauss_newton(
    S: np.ndarray, rho0: np.ndarray, w: np.ndarray, p: np.ndarray, b: np.ndarray, tol: float, max_iter: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Gauss–Newton from (p, b), vectorised over the epochs still moving: (p, b, steps, converged).

    Each step is the least-squares step, halved (up to :data:`MAX_HALVINGS` times) while it would increase
    χ² (a backtracking line search: near the solution the full step is taken, far from it the iteration
    cannot run away). An epoch converges when its full step is shorter than ``tol``, or promises a χ²
    decrease below what can be resolved. An epoch still moving after :data:`GN_STEPS` steps goes on with
    Newton's steps (:func:`_newton`), ``max_iter`` steps in all. The arithmetic is done about the receivers' centroid (coordinates
    of tens of kilometres for a ground network instead of 6·10⁶ m: the ranges are rounded a hundred times
    less, which matters where χ² is flat, as for a transmitter outside a planar network)."""
    E = len(p)
    origin = (
        np.sum(np.where(w[..., None] > 0, S, 0.0), axis=1) / np.maximum(np.sum(w > 0, axis=1), 1)[:, None]
    )
    S = S - origin[:, None, :]
    p = p - origin
    iterations = np.zeros(E, dtype=np.int64)
    converged = np.zeros(E, dtype=bool)
    active = np.ones(E, dtype=bool)
    for _ in range(min(max_iter, GN_STEPS)):
        idx = np.flatnonzero(active)
        if not idx.size:
            break
        Si, ri, wi, pi, bi = S[idx], rho0[idx], w[idx], p[idx], b[idx]
        step, Ri, _, _ = _qr_step(Si, ri, wi, pi, bi)
        ok = np.all(np.isfinite(step), axis=-1)
        step = np.where(ok[:, None], step, 0.0)
        # the χ² decrease the step promises, ‖R step‖² = ‖Qᵀ W^½ r‖², against what can be resolved: the
        # rounding of the residuals (ε (|ρ| + ‖S‖) per row, whitened) and the line search's own tolerance
        # (10⁻¹⁴ χ²): below it the fix cannot improve, whatever the step's length (an ill-conditioned geometry
        # magnifies rounding into steps longer than ``tol``, and along a flat valley of χ² the iteration
        # would wander)
        gain = np.sum(np.einsum("eij,ej->ei", Ri, step) ** 2, axis=-1)
        floor = 1e4 * np.sum((EPS * (np.abs(ri) + np.linalg.norm(Si, axis=-1)) * wi) ** 2, axis=-1)
        floor = floor + CHI2_RTOL * _chi2(Si, ri, wi, pi, bi)
        chi0 = _chi2(Si, ri, wi, pi, bi)
        slack = _chi2_rounding(Si, ri, wi, pi, bi)
        lam = np.ones(len(idx))
        for _ in range(MAX_HALVINGS):
            with np.errstate(over="ignore", invalid="ignore"):
                chi = _chi2(Si, ri, wi, pi + lam[:, None] * step[:, :3], bi + lam * step[:, 3])
            worse = ok & ~(chi <= chi0 + slack)
            if not worse.any():
                break
            lam = np.where(worse, 0.5 * lam, lam)
        ok &= np.linalg.norm(origin[idx] + pi + lam[:, None] * step[:, :3], axis=-1) < DIVERGED_M
        small = ok & ((np.linalg.norm(step, axis=-1) < tol) | (gain <= floor))
        lam = np.where(ok, lam, 0.0)
        p[idx] = pi + lam[:, None] * step[:, :3]
        b[idx] = bi + lam * step[:, 3]
        iterations[idx] += ok
        converged[idx[small]] = True
        active[idx[small | ~ok]] = False
    rest = np.flatnonzero(~converged & active & np.all(np.isfinite(p), axis=-1) & np.isfinite(b))
    if rest.size and max_iter > GN_STEPS:  # where Gauss–Newton crawls: Newton's steps with the full Hessian
        pn, bn, itn, okn = _newton(S[rest], rho0[rest], w[rest], p[rest], b[rest], tol, max_iter - GN_STEPS)
        p[rest], b[rest], iterations[rest] = pn, bn, iterations[rest] + itn
        converged[rest] = okn
    return p + origin, b, iterations, converged


def _newton(
    S: np.ndarray, rho0: np.ndarray, w: np.ndarray, p: np.ndarray, b: np.ndarray, tol: float, steps: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Newton's method on ½χ² from (p, b), with the full Hessian Σ w_i² (h_i h_iᵀ − r_i ∇²‖p − S_i‖),
    h_i = (u_i, 1), ∇²‖p − S_i‖ = (I − u_i u_iᵀ)/‖p − S_i‖ (the p block): quadratic convergence where
    Gauss–Newton converges only linearly, at a minimum with sizeable residuals along a direction the
    geometry hardly observes (the height of a transmitter outside a planar network). Where the Hessian is
    not positive definite the Gauss–Newton step is taken; each step is halved while χ² would increase.
    Returns (p, b, steps taken, converged: a step shorter than ``tol`` or than its own rounding)."""
    E = len(p)
    its = np.zeros(E, dtype=np.int64)
    conv = np.zeros(E, dtype=bool)
    eye = np.eye(3)
    for _ in range(steps):
        idx = np.flatnonzero(~conv)
        if not idx.size:
            break
        Si, ri, wi, pi, bi = S[idx], rho0[idx], w[idx], p[idx], b[idx]
        d = pi[:, None, :] - Si
        rng = np.linalg.norm(d, axis=-1)
        U = d / np.where(rng > 0, rng, 1.0)[..., None]
        r = np.where(wi > 0, ri - rng - bi[:, None], 0.0)
        w2 = wi**2
        h = np.concatenate([U, np.ones((*U.shape[:-1], 1))], axis=-1)
        grad = -np.einsum("ek,eki->ei", w2 * r, h)
        Hs = np.einsum("ek,eki,ekj->eij", w2, h, h)
        curv = (eye - U[..., :, None] * U[..., None, :]) / np.where(rng > 0, rng, 1.0)[..., None, None]
        Hs[:, :3, :3] -= np.einsum("ek,ekij->eij", w2 * r, curv)
        with np.errstate(all="ignore"):
            ev = np.linalg.eigvalsh(Hs)
            pd = ev[:, 0] > 1e-12 * np.abs(ev[:, -1])
            step = -np.linalg.solve(np.where(pd[:, None, None], Hs, np.eye(4)), grad[..., None])[..., 0]
            gn, _, _, _ = _qr_step(Si, ri, wi, pi, bi)
        step = np.where(pd[:, None], step, gn)
        ok = np.all(np.isfinite(step), axis=-1)
        step = np.where(ok[:, None], step, 0.0)
        chi0 = _chi2(Si, ri, wi, pi, bi)
        slack = _chi2_rounding(Si, ri, wi, pi, bi)
        lam = np.ones(len(idx))
        for _ in range(MAX_HALVINGS):
            with np.errstate(over="ignore", invalid="ignore"):
                chi = _chi2(Si, ri, wi, pi + lam[:, None] * step[:, :3], bi + lam * step[:, 3])
            worse = ok & ~(chi <= chi0 + slack)
            if not worse.any():
                break
            lam = np.where(worse, 0.5 * lam, lam)
        p[idx] = pi + lam[:, None] * step[:, :3]
        b[idx] = bi + lam * step[:, 3]
        its[idx] += ok
        # the step's own rounding: the gradient's, ε (|ρ| + ‖S‖ + ‖p‖) w² per row, through the Hessian's
        # inverse (1/λ_min); a step below 100 times that cannot be resolved (a fraction of a millimetre for
        # a transmitter 30 km outside a ground network, where χ² is flat in height)
        dg = np.sqrt(
            np.sum(
                (w2 * EPS * (np.abs(ri) + np.linalg.norm(Si, axis=-1) + np.linalg.norm(pi, axis=-1)[:, None]))
                ** 2,
                axis=-1,
            )
        )
        with np.errstate(divide="ignore", invalid="ignore"):
            noise = np.where(pd, 100.0 * dg / np.abs(ev[:, 0]), 0.0)
        small = ok & (np.linalg.norm(step, axis=-1) < tol + noise)
        conv[idx[small]] = True
        if not ok.any():
            break
    return p, b, its, conv


def _start_side(S: np.ndarray, used: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The receivers' plane of each epoch with its normal turned away from the Earth's centre ("above")."""
    centre, normal, flat = receiver_plane(S, used)
    up = np.sign(np.einsum("ei,ei->e", normal, centre))
    return centre, normal * np.where(up == 0, 1.0, up)[:, None], flat


def _closed_form(
    S: np.ndarray, rho0: np.ndarray, w: np.ndarray, used: np.ndarray, tol: float, max_iter: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Gauss–Newton from the closed-form solutions (:mod:`~motionsig_cli.surveillance.bancroft`).

    Candidates: both of Bancroft's roots, and for a nearly planar network the planar solution above the
    receivers' plane. Each is refined; the converged minimum with the lowest χ² is kept, and among minima
    that fit equally well (χ² equal to 10⁻⁶: with four receivers both roots fit exactly) the one nearest the
    ellipsoid (transmitters and receivers near the Earth: assumed). For a nearly planar network the start
    recorded is the planar solution above the plane, so that the caller's mirror-image rule keeps the fix
    above the receivers. Returns (p, b, iterations, converged, start (E, 3): NaN where the closed form
    failed)."""
    from motionsig_cli.surveillance.bancroft import bancroft, planar_start

    E = len(S)
    centre, normal, flat = _start_side(S, used)
    planar = flat < FLAT_RATIO
    cand_p, cand_b = bancroft(S, rho0, w)
    pl_p = np.full((E, 3), np.nan)
    pl_b = np.full(E, np.nan)
    if planar.any():
        pp, pb = planar_start(S[planar], rho0[planar], w[planar], centre[planar], normal[planar])
        pl_p[planar], pl_b[planar] = pp[:, 0], pb[:, 0]
    cand_p = np.concatenate([cand_p, pl_p[:, None]], axis=1)
    cand_b = np.concatenate([cand_b, pl_b[:, None]], axis=1)
    n = cand_p.shape[1]
    P = np.full((E, n, 3), np.nan)
    B = np.full((E, n), np.nan)
    IT = np.zeros((E, n), dtype=np.int64)
    OK = np.zeros((E, n), dtype=bool)
    chi = np.full((E, n), np.inf)
    for j in range(n):
        idx = np.flatnonzero(np.all(np.isfinite(cand_p[:, j]), axis=-1) & np.isfinite(cand_b[:, j]))
        if not idx.size:
            continue
        p, b, it, ok = _gauss_newton(S[idx], rho0[idx], w[idx], cand_p[idx, j].copy(), cand_b[idx, j].copy(),
                                     tol, max_iter)  # fmt: skip
        P[idx, j], B[idx, j], IT[idx, j], OK[idx, j] = p, b, it, ok
        chi[idx, j] = np.where(ok, _chi2(S[idx], rho0[idx], w[idx], p, b), np.inf)
    alt = np.abs(np.linalg.norm(np.where(np.isfinite(P), P, 0.0), axis=-1) - 6_371_000.0)
    cmin = np.min(chi, axis=1, keepdims=True)
    tie = OK & (chi <= cmin + 1e-6 * (1.0 + np.where(np.isfinite(cmin), cmin, 0.0)))
    any_ok = OK.any(axis=1)
    # converged: the best fit (nearest the Earth among ties); none converged: the first candidate that ran
    first = np.argmax(np.all(np.isfinite(P), axis=-1), axis=1)
    j = np.where(any_ok, np.argmin(np.where(tie, alt, np.inf), axis=1), first)
    r = np.arange(E)
    start = np.where(planar[:, None] & np.all(np.isfinite(pl_p), axis=-1)[:, None], pl_p, cand_p[r, j])
    has = np.all(np.isfinite(P[r, j]), axis=-1)
    start = np.where(has[:, None], start, np.nan)
    return P[r, j], B[r, j], IT[r, j], OK[r, j], start


def solve_snapshot(
    rho: np.ndarray,
    receivers: np.ndarray,
    *,
    sigma: np.ndarray | float | None = None,
    p0: np.ndarray | None = None,
    b0: np.ndarray | None = None,
    scale: str = "none",
    tol: float = 1e-6,
    max_iter: int = 20,
    retry: bool = True,
    mirror: bool = True,
    on_failure: str = "raise",
) -> SnapshotFix:
    """Weighted least-squares fixes of position and clock at E epochs (module docstring).

    Args:
        rho: (E, K) pseudoranges c(T − t) [m]; NaN: receiver absent at that epoch.
        receivers: (K, 3) or (E, K, 3) ECEF positions [m] (ignored where ``rho`` is NaN, and may be NaN
            there).
        sigma: σ of each pseudorange [m]: (E, K), a scalar, or None (unit weights: then give a ``scale``
            other than ``"none"`` for a meaningful covariance).
        p0: (E, 3) or (3,) starting points [m]; default the closed-form solution of each epoch
            (:mod:`~motionsig_cli.surveillance.bancroft`), or :func:`default_start` where that fails.
        b0: (E,) starting clock offsets b [m]; default the weighted mean of ρ − ‖p0 − S‖.
        scale: one of :data:`SCALES`.
        tol: stop when the step (x, y, z, b) is shorter than this [m].
        max_iter: at most this many steps.
        retry: restart an epoch that did not converge from the fix of the nearest converged epoch (the
            previous one, else the next one): the previous epoch's fix is the natural start of a track.
        mirror: for receivers nearly in one plane (flatness below :data:`FLAT_RATIO`), also start from the
            fix's mirror image in their plane, and keep the minimum on the starting point's side of the
            plane (the two fit about equally well: the data cannot tell them apart, the start says where
            the transmitter is; the closed-form start is above the plane); the other one's χ² is kept in
            ``other_chi2``.
        on_failure: ``"raise"`` (a :class:`SingularGeometry` for the first epoch that cannot be solved) or
            ``"flag"`` (every epoch is solved that can be; the others get a ``status``, NaN values).

    Raises:
        SingularGeometry: (``on_failure="raise"``) an epoch with fewer than :data:`MIN_RECEIVERS` receivers,
            or a singular geometry.
        ConfigError: a bad ``scale``, ``tol``, ``max_iter`` or ``on_failure``.
    """
    one_of("scale", scale, SCALES)
    one_of("on_failure", on_failure, ("raise", "flag"))
    positive("tol", tol, unit="m")
    integer("max_iter", max_iter, 1, 1000)
    rho = np.atleast_2d(np.asarray(rho, dtype=float))
    E, K = rho.shape
    S = _broadcast(receivers, E, K)
    used = np.isfinite(rho) & np.all(np.isfinite(S), axis=-1)
    S = np.where(used[..., None], S, 0.0)  # an absent receiver's position (NaN) never reaches the algebra
    sig = np.broadcast_to(np.asarray(1.0 if sigma is None else sigma, dtype=float), (E, K))
    if np.any(used & ~(sig > 0)):
        raise ConfigError("sigma", float(np.min(sig[used])), "is not > 0 for every measurement used")
    n_used = used.sum(axis=1)
    few = n_used < MIN_RECEIVERS
    if few.any():
        if on_failure == "raise":
            e = int(np.flatnonzero(few)[0])
            raise SingularGeometry(
                e, f"{int(n_used[e])} receiver(s): at least {MIN_RECEIVERS} are needed for a fix"
            )
        keep = ~few
        sub = None
        if keep.any():
            sub = solve_snapshot(
                np.where(used, rho, np.nan)[keep], S[keep], sigma=np.where(used, sig, 1.0)[keep],
                p0=None if p0 is None else np.broadcast_to(p0, (E, 3))[keep],
                b0=None if b0 is None else np.broadcast_to(b0, (E,))[keep], scale="none", tol=tol,
                max_iter=max_iter, retry=retry, mirror=mirror, on_failure="flag",
            )  # fmt: skip
        fix = _expand(sub, keep, n_used, K)
        return scale_covariance(fix, scale)
    w = np.where(used, 1.0 / np.where(used, sig, 1.0), 0.0)
    rho0 = np.where(used, rho, 0.0)
    started = np.full(E, "given" if p0 is not None else "closed form", dtype=object)
    if p0 is None:
        p, b, iterations, converged, p_start = _closed_form(S, rho0, w, used, tol, max_iter)
        lost_cf = np.any(np.isnan(p_start), axis=-1)
        if lost_cf.any():  # the closed form failed: the old start, 10 km above the receivers' centroid
            i = np.flatnonzero(lost_cf)
            p_start[i] = default_start(S[i], used[i])
            p[i], b[i], iterations[i], converged[i] = _gauss_newton(
                S[i], rho0[i], w[i], p_start[i].copy(), _mean_bias(S[i], rho0[i], w[i], p_start[i]), tol, max_iter
            )  # fmt: skip
            started[i] = "centroid"
        bad = ~np.all(np.isfinite(p), axis=-1) | ~np.isfinite(b)
        if bad.any():  # a start that ran away: the centroid start
            i = np.flatnonzero(bad)
            p_start[i] = default_start(S[i], used[i])
            p[i], b[i], iterations[i], converged[i] = _gauss_newton(
                S[i], rho0[i], w[i], p_start[i].copy(), _mean_bias(S[i], rho0[i], w[i], p_start[i]), tol, max_iter
            )  # fmt: skip
            started[i] = "centroid"
    else:
        p = np.array(np.broadcast_to(p0, (E, 3)), dtype=float)
        b = _mean_bias(S, rho0, w, p) if b0 is None else np.array(np.broadcast_to(b0, (E,)), dtype=float)
        p_start = p.copy()
        p, b, iterations, converged = _gauss_newton(S, rho0, w, p, b, tol, max_iter)
    retried = np.zeros(E, dtype=bool)
    failed = np.flatnonzero(~converged)
    good = np.flatnonzero(converged)
    if retry and failed.size and good.size:  # restart from the nearest converged epoch's fix
        j = np.searchsorted(good, failed) - 1
        near = good[np.where(j >= 0, j, 0)]
        near = np.where(j >= 0, near, good[0])
        p2, b2, it2, ok2 = _gauss_newton(
            S[failed], rho0[failed], w[failed], p[near].copy(), b[near].copy(), tol, max_iter
        )
        take = failed[ok2]
        p[take], b[take], iterations[take] = p2[ok2], b2[ok2], iterations[take] + it2[ok2]
        converged[take] = True
        retried[failed] = True
    mirrored = np.zeros(E, dtype=bool)
    other_chi2 = np.full(E, np.nan)
    if mirror:  # a nearly planar network: the fix's mirror image in the plane is the other candidate
        centre, normal, flat = receiver_plane(S, used)
        cand = np.flatnonzero(converged & (flat < FLAT_RATIO))
        if cand.size:
            Sc, rc, wc, nc = S[cand], rho0[cand], w[cand], normal[cand]
            d = np.einsum("ei,ei->e", p[cand] - centre[cand], nc)
            pm = p[cand] - 2.0 * d[:, None] * nc
            p2, b2, it2, ok2 = _gauss_newton(Sc, rc, wc, pm, _mean_bias(Sc, rc, wc, pm), tol, max_iter)
            ok2 &= np.linalg.norm(p2 - p[cand], axis=-1) > 1.0  # another minimum, not the same one
            chi_a, chi_b = _chi2(Sc, rc, wc, p[cand], b[cand]), _chi2(Sc, rc, wc, p2, b2)
            side0 = np.einsum("ei,ei->e", p_start[cand] - centre[cand], nc)
            side2 = np.einsum("ei,ei->e", p2 - centre[cand], nc)
            # the start's side of the plane decides; a start in the plane leaves it to the fit
            take_b = ok2 & np.where(
                np.abs(side0) > 1.0, (side2 * side0 > 0) & (d * side0 <= 0), chi_b < chi_a
            )
            take = cand[take_b]
            p[take], b[take], iterations[take] = p2[take_b], b2[take_b], it2[take_b]
            mirrored[take] = True
            other_chi2[cand] = np.where(ok2, np.where(take_b, chi_a, chi_b), np.nan)
    # the solution: residuals, covariance (whitened R), geometry (unweighted)
    lost = ~(np.all(np.isfinite(p), axis=-1) & np.isfinite(b))
    p = np.where(lost[:, None], p_start, p)
    b = np.where(lost, _mean_bias(S, rho0, w, p), b)
    converged &= ~lost
    _, R, r, U = _qr_step(S, rho0, w, p, b)
    cond = _cond(U, used)
    bad = ~(cond <= COND_LIMIT)
    if np.any(bad & ~converged):  # diverged to a singular point, or singular everywhere? look at the start
        idx = np.flatnonzero(bad & ~converged)
        U0 = _qr_step(S[idx], rho0[idx], w[idx], p_start[idx], b[idx])[3]
        fine = _cond(U0, used[idx]) <= COND_LIMIT
        bad[idx[fine]] = False  # not the geometry: an epoch that did not converge (its fix is flagged)
        lost[idx[fine]] = True
    lost |= ~converged
    status = np.where(converged, "", "no convergence").astype(object)
    if np.any(bad):
        if on_failure == "raise":
            e = int(np.flatnonzero(bad)[0])
            raise SingularGeometry(
                e,
                f"the geometry is singular (condition number {cond[e]:.3g} > {COND_LIMIT:g}): position and clock "
                "cannot be separated (e.g. all receivers on a line, or in a plane with the transmitter)",
            )
        status[bad] = "singular geometry"
        converged &= ~bad
        lost |= bad
    eye = np.eye(4)
    Rf = np.where(lost[:, None, None] | ~np.isfinite(R), eye, R)
    sv = np.linalg.svd(Rf, compute_uv=False)
    lost |= ~(sv[:, -1] > 0)
    Rinv = np.linalg.inv(np.where(lost[:, None, None], eye, Rf))
    cov = Rinv @ np.swapaxes(Rinv, -1, -2)  # (HᵀWH)⁻¹ = R⁻¹R⁻ᵀ
    H = np.concatenate([U, np.ones((E, K, 1))], axis=-1) * used[..., None]
    Rh = thin_qr(np.where(lost[:, None, None], np.eye(K, 4), H))[1]
    Rhi = np.linalg.inv(np.where(lost[:, None, None], eye, Rh))
    G = Rhi @ np.swapaxes(Rhi, -1, -2)  # (HᵀH)⁻¹
    cov[lost] = np.nan
    G[lost] = np.nan
    res = np.where(used, r, np.nan)
    z = res * np.where(used, w, np.nan)
    chi2 = np.nansum(z**2, axis=1)
    lat, lon, _ = ecef_to_geodetic(p, strict=False)
    Genu = covariance_to_enu(G[:, :3, :3], lat, lon)
    fix = SnapshotFix(
        position=p,
        bias=b,
        covariance=0.5 * (cov + np.swapaxes(cov, -1, -2)),
        gdop=np.sqrt(np.trace(G, axis1=-2, axis2=-1)),
        pdop=np.sqrt(np.trace(G[:, :3, :3], axis1=-2, axis2=-1)),
        hdop=np.sqrt(Genu[:, 0, 0] + Genu[:, 1, 1]),
        vdop=np.sqrt(Genu[:, 2, 2]),
        tdop=np.sqrt(G[:, 3, 3]),
        residuals=res,
        normalised=z,
        rms_residual=np.sqrt(np.nanmean(res**2, axis=1)),
        chi2=chi2,
        variance_factor=np.ones(E),
        n_used=n_used,
        iterations=iterations,
        converged=converged,
        retried=retried,
        mirrored=mirrored,
        other_chi2=other_chi2,
        cond=cond,
        scale="none",
        status=status,
        started=started,
    )
    return scale_covariance(fix, scale)


def scale_covariance(fix: SnapshotFix, scale: str) -> SnapshotFix:
    """The fixes with their covariance (unscaled, ``fix.scale == "none"``) multiplied by the a-posteriori
    variance factor s² = rᵀWr/(K − 4) of each epoch (``"epoch"``: an epoch without redundancy, K = 4,
    takes the pooled factor of the others) or of all epochs pooled (``"pooled"``: Σ rᵀWr / Σ (K − 4) over
    the epochs with a fix), or unscaled (``"none"``)."""
    one_of("scale", scale, SCALES)
    if fix.scale != "none":
        raise ValueError("scale_covariance takes unscaled fixes")
    ok = fix.ok
    dof = np.where(ok, fix.n_used - MIN_RECEIVERS, 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        pooled = float(np.sum(np.where(ok, fix.chi2, 0.0)) / np.sum(dof)) if np.sum(dof) > 0 else np.nan
        per_epoch = np.where(dof > 0, fix.chi2 / np.maximum(dof, 1), pooled)
    E = len(fix.chi2)
    factor = {"none": np.ones(E), "epoch": per_epoch, "pooled": np.full(E, pooled)}[scale]
    return replace(
        fix, covariance=fix.covariance * factor[:, None, None], variance_factor=factor, scale=scale
    )


def _expand(sub: SnapshotFix | None, keep: np.ndarray, n_used: np.ndarray, K: int) -> SnapshotFix:
    """Fixes of the epochs ``keep`` spread over all E epochs; the others "too few receivers"."""
    E = len(keep)
    out: dict[str, object] = {}
    for f in fields(SnapshotFix):
        if f.name == "scale":
            out[f.name] = "none"
            continue
        v = None if sub is None else getattr(sub, f.name)
        shape = {"position": (3,), "covariance": (4, 4), "residuals": (K,), "normalised": (K,)}.get(
            f.name, ()
        )
        if f.name in ("converged", "retried", "mirrored"):
            a = np.zeros(E, dtype=bool)
        elif f.name in ("n_used", "iterations"):
            a = np.zeros(E, dtype=np.int64)
        elif f.name in ("status", "started"):
            a = np.full(E, "too few receivers" if f.name == "status" else "", dtype=object)
        else:
            a = np.full((E, *shape), np.nan)
        if v is not None:
            a[keep] = v
        out[f.name] = a
    out["n_used"] = n_used
    return SnapshotFix(**out)  # type: ignore[arg-type]


# --- the report's clock pseudo-measurement with weights (§4.5) ------------------------------------------


@dataclass(frozen=True)
class WeightedPseudo:
    """Epochs linearised at p* and reduced to their clock pseudo-measurements, whitened by the weights
    (arrays over leading axes ``...`` — runs — and the K receiver slots; an absent receiver has weight 0).

    Attributes:
        z: (..., K) whitened ρ − ‖p* − S‖ [m/σ] (0 where absent).
        ones: (..., K) the whitened clock column 1/σ_i (0 where absent).
        Q, R: thin QR of the whitened directions W^½U (..., K, 3) and (..., 3, 3).
        beta: (...) β̃ = 1̃ᵀ(I − P̃)1̃ [1/m²]; the pseudo-measurement's variance is 1/β̃ (0 with three
            receivers: no clock information).
        y: (...) the clock pseudo-measurement 1̃ᵀ(I − P̃)z̃/β̃ [m] (NaN with three receivers).
    """

    z: np.ndarray
    ones: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    beta: np.ndarray
    y: np.ndarray


def weighted_pseudo_measurement(
    rho: np.ndarray, receivers: np.ndarray, weight: np.ndarray, p_star: np.ndarray
) -> WeightedPseudo:
    """The report's reduction of an epoch to y = b + v (ATC-10 §4.5, eqs 4.5.2 and 4.5.16–4.5.20), with
    weights: whiten the rows by w_i = 1/σ_i, then y = 1̃ᵀ(I − P̃)z̃/β̃ with Var v = 1/β̃, uncorrelated with
    the position part. With equal σ it is
    :func:`~motionsig_cli.surveillance.clock_tracking.pseudo_measurement` (in metres instead of c = 1
    units), with β̃ = β/σ².

    Args:
        rho: (..., K) pseudoranges [m] (any value where the weight is 0).
        receivers: (..., K, 3) ECEF positions [m] (broadcast).
        weight: (..., K) 1/σ [1/m], 0 for an absent receiver; at least three nonzero.
        p_star: (..., 3) linearisation point [m].
    """
    d = np.asarray(p_star, float)[..., None, :] - receivers
    rng = np.linalg.norm(d, axis=-1)
    U = d / np.where(rng > 0, rng, 1.0)[..., None]
    wt = np.asarray(weight, float)
    wt, rng = np.broadcast_arrays(wt, rng)
    z = np.where(wt > 0, (np.where(wt > 0, rho, 0.0) - rng) * wt, 0.0)
    Q, R = thin_qr(U * wt[..., None])
    w = wt - np.einsum("...kj,...j->...k", Q, np.einsum("...kj,...k->...j", Q, wt))  # (I − Q̃Q̃ᵀ)1̃
    beta = np.einsum("...k,...k->...", w, w)
    has_clock = np.sum(wt > 0, axis=-1) > 3
    beta = np.where(has_clock, beta, 0.0)  # exactly: three receivers span the directions (eq 4.5.2)
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.where(has_clock, np.einsum("...k,...k->...", w, z) / np.where(has_clock, beta, 1.0), np.nan)
    return WeightedPseudo(z, wt, Q, R, beta, y)


def weighted_position_update(pm: WeightedPseudo, p_star: np.ndarray, b: np.ndarray) -> np.ndarray:
    """p̂ = p* + (ŨᵀŨ)⁻¹Ũᵀ(z̃ − b·1̃) = p* + R⁻¹Qᵀ(z̃ − b 1̃) (eqs 4.5.4, 4.5.17, 4.5.28, whitened)."""
    r = pm.z - np.asarray(b, float)[..., None] * pm.ones
    return np.asarray(p_star, float) + solve_upper(pm.R, np.einsum("...kj,...k->...j", pm.Q, r))


def position_covariance(pm: WeightedPseudo, clock_var: np.ndarray) -> np.ndarray:
    """Covariance (..., 3, 3) [m²] of :func:`weighted_position_update` when the clock estimate has variance
    ``clock_var`` [m²] and is uncorrelated with the position part of the epoch's errors (true for the
    report's estimator: its innovation uses only the part of the errors outside the span of the
    directions, and an outage epoch does not update the clock): (ŨᵀŨ)⁻¹ + V vvᵀ with v = (ŨᵀŨ)⁻¹Ũᵀ1̃
    (its trace is eq 4.5.35, corrected, in c = 1 units: σ²tr + V b)."""
    Rinv = np.linalg.inv(pm.R)
    base = Rinv @ np.swapaxes(Rinv, -1, -2)
    v = np.einsum("...ij,...j->...i", Rinv, np.einsum("...kj,...k->...j", pm.Q, pm.ones))
    P = base + np.asarray(clock_var, float)[..., None, None] * np.einsum("...i,...j->...ij", v, v)
    return 0.5 * (P + np.swapaxes(P, -1, -2))
