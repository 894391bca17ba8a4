"""Motion models of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System* ("the
paper").

Two state layouts:

* **Input model** (GLR/MLR, §II): x = [x, ẋ, y, ẏ], nearly constant velocity with a piecewise-constant
  acceleration input u = [u_x, u_y]: x_{k+1} = F x_k + G_u u_k + w_k, G_u = [[T²/2, 0], [T, 0], [0, T²/2],
  [0, T]], w continuous white-noise acceleration of psd q̃₀.
* **IMM model set** (eqs 7–8, §IV): X = [x, ẋ, y, ẏ, ẍ, ÿ]; model 1 is constant velocity with the
  acceleration rows of Φ₁ zero and Q₁ = 0; models 2 and 3 are constant acceleration with an acceleration
  increment of covariance Q₂ = 0.001 I, Q₃ = 0.0144 I through G₂ = G₃.

The paper prints G₂ with T (not T/2) in the ẏ row; the x column (T²/4, T/2, 1) is the trapezoidal model
x⁺ = x + vT + (T²/2)(a_k + a_{k+1})/2 with a_{k+1} = a_k + w, so the y column is (T²/4, T/2, 1) too
(``paper-fixed``, the default). ``standard`` is the common discrete white-noise-jerk form (T²/2, T, 1).

**Irregular time.** Every model is a function of the step Δt between two processed measurements, as in any
tracker fed by a real sensor (Stone Soup's transition models take the time interval of each predict):
:func:`cv_input_steps` gives F(Δt), G_u(Δt), Q(Δt) of the input model, and a :class:`ModelSet` carries
``steps``, which gives Φ_j(Δt), G_j Q_j G_jᵀ(Δt) and Π(Δt) for an array of steps at once. On a regular grid
(Δt = T at every step) they are the matrices above, bit for bit. Two IMM model sets:

* :func:`imm_models` (the paper's, §IV): Φ_j(Δt) and G_j(Δt) with the printed T replaced by Δt, the
  *discrete* increment variances q_j per step and Π per step, as printed (the paper has one period);
* :func:`aircraft_models` (for real aircraft): the same three state layouts as continuous-time models —
  CV with white-noise acceleration of psd q̃₁ [m²/s³] (acceleration rows zero), and two Wiener-process
  acceleration (white-noise jerk) models of psd q̃₂, q̃₃ [m²/s⁵]:

      Q_CV(Δt) = q̃ [[Δt³/3, Δt²/2], [Δt²/2, Δt]],                                         (M1)
      Q_CA(Δt) = q̃ [[Δt⁵/20, Δt⁴/8, Δt³/6], [Δt⁴/8, Δt³/3, Δt²/2], [Δt³/6, Δt²/2, Δt]]     (M2)

  per axis (Bar-Shalom, Li & Kirubarajan 2001, §6.2.2 and §6.2.3), and the switching of a continuous-time
  Markov chain with mean sojourn τ_i in model i, p_ii(Δt) = exp(−Δt/τ_i), the rest shared equally (M3).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of, positive

__all__ = [
    "G2_FORMS",
    "H_POS4",
    "H_POS6",
    "Q0_RANGE",
    "ModelSet",
    "aircraft_models",
    "check_distribution",
    "check_transition",
    "coordinated_turn_models",
    "cv_input_model",
    "cv_input_steps",
    "imm_models",
    "two_point_init",
    "two_point_restart",
]

G2_FORMS = ("paper-fixed", "standard")
"""Forms of the maneuvering models' noise gain G₂ = G₃ (``paper-fixed``: the printed form, corrected)."""

H_POS4 = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
"""Position measurement of the 4-D state [x, ẋ, y, ẏ]."""
H_POS6 = np.array([[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]])
"""Position measurement of the 6-D state [x, ẋ, y, ẏ, ẍ, ÿ] (H of eq 8)."""

PI_PAPER = ((0.95, 0.025, 0.025), (0.025, 0.95, 0.025), (0.025, 0.025, 0.95))
"""Markov transition matrix of the paper, p_ij = P(model j at k | model i at k − 1) (§IV)."""
MU0_PAPER = (0.8, 0.1, 0.1)
"""Initial model probabilities (§IV; the paper calls them "transition probabilities")."""
Q_PAPER = (0.0, 0.001, 0.0144)
"""Per-model acceleration-increment variances: Q₁ = 0, Q₂ = 0.001 I, Q₃ = 0.0144 I (§IV)."""


Q0_RANGE = (0.0, 1e6)
"""Acceleration psd q̃₀ of the input model accepted [m²/s³]: 0 is the exact constant-velocity model; 1e6 m²/s³
(a velocity random walk of 1 km/s in one second) is far beyond any vehicle, and keeps Q far from overflow."""

PROB_TOL = 1e-9
"""Tolerance of a probability vector's sum."""


def _check_T(T: float) -> None:
    positive("T", T, unit="s")


def check_transition(field_name: str, Pi: Any, r: int | None = None) -> np.ndarray:
    """``Pi`` as a float array if it is a Markov transition matrix (r × r when ``r`` is given): finite, every
    row non-negative and summing to 1; else :class:`~motionsig_cli.config.ConfigError` on ``field_name``."""
    try:
        a = np.asarray(Pi, float)
    except (TypeError, ValueError):
        raise ConfigError(field_name, Pi, "is not a matrix of numbers") from None
    k = a.shape[0] if a.ndim == 2 else -1
    if a.shape != (k, k) or (r is not None and k != r):
        want = f"{r} rows of {r} probabilities (one per model)" if r is not None else "a square matrix"
        raise ConfigError(field_name, a.tolist(), f"is not {want}")
    for i, row in enumerate(a):
        if not (np.all(np.isfinite(row)) and np.all(row >= 0) and abs(row.sum() - 1.0) <= PROB_TOL):
            raise ConfigError(
                field_name, row.tolist(), f"is row {i + 1}: its entries must be non-negative and sum to 1"
            )
    return a


def check_distribution(field_name: str, p: Any, r: int | None = None) -> np.ndarray:
    """``p`` as a float array if it is a probability vector (of ``r`` entries when given): finite,
    non-negative, summing to 1; else :class:`~motionsig_cli.config.ConfigError` on ``field_name``."""
    try:
        a = np.asarray(p, float)
    except (TypeError, ValueError):
        raise ConfigError(field_name, p, "is not a vector of numbers") from None
    if a.ndim != 1 or (r is not None and a.size != r):
        want = f"{r} probabilities (one per model)" if r is not None else "a vector"
        raise ConfigError(field_name, a.tolist(), f"is not {want}")
    if not (np.all(np.isfinite(a)) and np.all(a >= 0) and abs(a.sum() - 1.0) <= PROB_TOL):
        raise ConfigError(field_name, a.tolist(), "is not a probability vector (non-negative, summing to 1)")
    return a


def cv_input_model(T: float, q0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """F, G_u and Q of the GLR/MLR input model (§II).

    Returns:
        F (4, 4), G_u (4, 2) and Q = q̃₀ blockdiag([[T³/3, T²/2], [T²/2, T]]) (4, 4), state [x, ẋ, y, ẏ].
    """
    _check_T(T)
    F, G, Q = cv_input_steps(np.float64(T), q0)
    return F, G, Q


def cv_input_steps(dt: np.ndarray, q0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """F(Δt) (..., 4, 4), G_u(Δt) (..., 4, 2) and Q(Δt) (..., 4, 4) of the input model for an array of steps
    Δt [s] (> 0) — :func:`cv_input_model` for every step at once (eq M1 for Q)."""
    in_range("q0", q0, *Q0_RANGE, unit="m²/s³")
    dt = np.asarray(dt, float)
    lead = dt.shape
    F = np.broadcast_to(np.eye(4), (*lead, 4, 4)).copy()
    F[..., 0, 1] = F[..., 2, 3] = dt  # per axis [[1, Δt], [0, 1]]
    G = np.zeros((*lead, 4, 2))
    G[..., 0, 0] = G[..., 2, 1] = dt * dt / 2
    G[..., 1, 0] = G[..., 3, 1] = dt
    Q = np.zeros((*lead, 4, 4))
    for o in (0, 2):  # continuous white-noise acceleration, eq M1
        Q[..., o, o] = q0 * dt**3 / 3
        Q[..., o, o + 1] = Q[..., o + 1, o] = q0 * dt**2 / 2
        Q[..., o + 1, o + 1] = q0 * dt
    return F, G, Q


def _phi_cv6(T: float | np.ndarray) -> np.ndarray:
    """Φ₁: constant velocity on the 6-D state, acceleration rows zero (§IV); (..., 6, 6) for an array T."""
    T = np.asarray(T, float)
    P = np.zeros((*T.shape, 6, 6))
    P[..., 0, 0] = P[..., 1, 1] = P[..., 2, 2] = P[..., 3, 3] = 1.0
    P[..., 0, 1] = P[..., 2, 3] = T
    return P


def _phi_ca6(T: float | np.ndarray) -> np.ndarray:
    """Φ₂ = Φ₃: constant acceleration (§IV); (..., 6, 6) for an array T."""
    T = np.asarray(T, float)
    P = np.broadcast_to(np.eye(6), (*T.shape, 6, 6)).copy()
    P[..., 0, 1] = P[..., 2, 3] = T
    P[..., 0, 4] = P[..., 2, 5] = T * T / 2
    P[..., 1, 4] = P[..., 3, 5] = T
    return P


def _g_ca6(T: float | np.ndarray, form: str) -> np.ndarray:
    """G₂ = G₃ (§IV): ``paper-fixed`` (T²/4, T/2, 1) per axis, or ``standard`` (T²/2, T, 1)."""
    one_of("g2", form, G2_FORMS)
    T = np.asarray(T, float)
    if form == "paper-fixed":
        a, b = T * T / 4, T / 2
    else:
        a, b = T * T / 2, T
    G = np.zeros((*T.shape, 6, 2))
    G[..., 0, 0] = G[..., 2, 1] = a
    G[..., 1, 0] = G[..., 3, 1] = b
    G[..., 4, 0] = G[..., 5, 1] = 1.0
    return G


def _g_cv6(T: float | np.ndarray) -> np.ndarray:
    """G₁ as printed (irrelevant while Q₁ = 0)."""
    T = np.asarray(T, float)
    G = np.zeros((*T.shape, 6, 2))
    G[..., 0, 0] = G[..., 2, 1] = T * T / 2
    G[..., 1, 0] = G[..., 3, 1] = T
    return G


def _q_cv6(dt: np.ndarray, q: float) -> np.ndarray:
    """Q_CV(Δt) of eq M1 per axis on the 6-D state (acceleration rows zero), (..., 6, 6)."""
    Q = np.zeros((*dt.shape, 6, 6))
    for o in (0, 2):
        Q[..., o, o] = q * dt**3 / 3
        Q[..., o, o + 1] = Q[..., o + 1, o] = q * dt**2 / 2
        Q[..., o + 1, o + 1] = q * dt
    return Q


def _q_ca6(dt: np.ndarray, q: float) -> np.ndarray:
    """Q_CA(Δt) of eq M2 per axis (position, velocity, acceleration of x at 0, 1, 4; of y at 2, 3, 5)."""
    c = np.stack(
        [
            np.stack([dt**5 / 20, dt**4 / 8, dt**3 / 6], -1),
            np.stack([dt**4 / 8, dt**3 / 3, dt**2 / 2], -1),
            np.stack([dt**3 / 6, dt**2 / 2, dt], -1),
        ],
        -2,
    )  # (..., 3, 3)
    Q = np.zeros((*dt.shape, 6, 6))
    for idx in ((0, 1, 4), (2, 3, 5)):
        Q[..., np.ix_(idx, idx)[0], np.ix_(idx, idx)[1]] = q * c
    return Q


@dataclass(frozen=True)
class ModelSet:
    """r linear models of a jump-Markov system (eq 7) with a common measurement (eq 8).

    Attributes:
        Phi: (r, n, n) transition matrices Φ_j.
        Qd: (r, n, n) process-noise covariances G_j Q_j G_jᵀ.
        Pi: (r, r) transition matrix, Pi[i, j] = P(model j at k | model i at k − 1).
        mu0: (r,) model probabilities at the initialisation scan.
        names: one label per model.
        steps: None (the model set has one period), or the model set as a function of the step:
            ``steps(dt)`` for an array of steps Δt [s] of shape S gives (Φ (S, r, n, n), Qd (S, r, n, n),
            Π (S, r, r)) — what :func:`motionsig_cli.filters.imm.imm_filter` uses on irregular times.

    Examples:
        Two scalar random-walk models of different noise, switching with probability 0.1:

        >>> import numpy as np
        >>> from motionsig_cli import ModelSet
        >>> ms = ModelSet(Phi=np.ones((2, 1, 1)), Qd=np.array([[[0.1]], [[10.0]]]),
        ...               Pi=[[0.9, 0.1], [0.1, 0.9]], mu0=[0.5, 0.5], names=("quiet", "agile"))
        >>> ms.r, ms.n, ms.names
        (2, 1, ('quiet', 'agile'))
    """

    Phi: np.ndarray
    Qd: np.ndarray
    Pi: np.ndarray
    mu0: np.ndarray
    names: tuple[str, ...] = field(default=())
    steps: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = field(
        default=None, compare=False, repr=False
    )

    def __post_init__(self) -> None:
        Phi, Qd = np.asarray(self.Phi, float), np.asarray(self.Qd, float)
        Pi, mu0 = np.asarray(self.Pi, float), np.asarray(self.mu0, float)
        if Phi.ndim != 3 or Phi.shape[1] != Phi.shape[2]:
            raise ConfigError("Phi", Phi.shape, "is not the shape (r, n, n) of r transition matrices")
        if Qd.shape != Phi.shape:
            raise ConfigError("Qd", Qd.shape, f"is not the shape {Phi.shape} of Phi")
        r = Phi.shape[0]
        for name, a in (("Phi", Phi), ("Qd", Qd)):
            if not np.all(np.isfinite(a)):
                raise ConfigError(name, a.shape, "has non-finite entries")
        Pi = check_transition("Pi", Pi, r)
        mu0 = check_distribution("mu0", mu0, r)
        tol = -1e-12 * max(1.0, float(np.abs(Qd).max()))
        low = np.linalg.eigvalsh(0.5 * (Qd + np.swapaxes(Qd, 1, 2)))[:, 0]
        for j in range(r):
            if not np.allclose(Qd[j], Qd[j].T, atol=0, rtol=1e-12) or low[j] < tol:
                reason = f"(model {j + 1}) is not symmetric positive semi-definite"
                raise ConfigError("Qd", Qd[j].tolist(), reason)
        names = self.names or tuple(f"model {j + 1}" for j in range(r))
        if len(names) != r:
            raise ConfigError("names", tuple(names), f"has {len(names)} names for {r} models")
        for k, v in (("Phi", Phi), ("Qd", Qd), ("Pi", Pi), ("mu0", mu0)):
            v.setflags(write=False)
            object.__setattr__(self, k, v)
        object.__setattr__(self, "names", tuple(names))

    @property
    def r(self) -> int:
        """Number of models."""
        return int(self.Phi.shape[0])

    @property
    def n(self) -> int:
        """State dimension."""
        return int(self.Phi.shape[1])


def imm_models(
    T: float,
    *,
    g2: str = "paper-fixed",
    q: tuple[float, float, float] = Q_PAPER,
    Pi: np.ndarray | tuple[tuple[float, ...], ...] = PI_PAPER,
    mu0: np.ndarray | tuple[float, ...] = MU0_PAPER,
) -> ModelSet:
    """The paper's three models (§IV): CV (Q₁ = 0) and two CA models (Q₂, Q₃) on X (6-D).

    Args:
        T: scan period [s].
        g2: ``paper-fixed`` (default) or ``standard`` form of G₂ = G₃.
        q: acceleration-increment variances (q₁, q₂, q₃); model j's noise is q_j G_j G_jᵀ.
        Pi: transition matrix, Pi[i, j] = P(model j at k | model i at k − 1).
        mu0: initial model probabilities.

    Examples:
        >>> from motionsig_cli import imm_models
        >>> ms = imm_models(2.0)  # T = 2 s, the paper's Q_j, Π and μ0
        >>> ms.r, ms.n, ms.names
        (3, 6, ('CV', 'CA q=0.001', 'CA q=0.0144'))
    """
    _check_T(T)
    if len(q) != 3 or not all(math.isfinite(v) and v >= 0 for v in q):
        raise ConfigError("q", tuple(q), "is not three finite variances >= 0")
    one_of("g2", g2, G2_FORMS)
    Pi_a = check_transition("Pi", Pi, 3)

    def steps(dt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        dt = np.asarray(dt, float)
        G1, G2 = _g_cv6(dt), _g_ca6(dt, g2)
        G1T, G2T = np.swapaxes(G1, -1, -2), np.swapaxes(G2, -1, -2)
        Phi = np.stack([_phi_cv6(dt), _phi_ca6(dt), _phi_ca6(dt)], axis=-3)
        # G_j Q_j G_jᵀ, Q_j = q_j I₂ (a discrete variance per step, as printed)
        Qd = np.stack([q[0] * G1 @ G1T, q[1] * G2 @ G2T, q[2] * G2 @ G2T], axis=-3)
        return Phi, Qd, np.broadcast_to(Pi_a, (*dt.shape, 3, 3))

    Phi, Qd, _ = steps(np.float64(T))
    return ModelSet(
        Phi,
        Qd,
        Pi_a,
        np.asarray(mu0, float),
        names=("CV", f"CA q={q[1]:g}", f"CA q={q[2]:g}"),
        steps=steps,
    )


def _switching(dt: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Π(Δt) (..., 3, 3) of a continuous-time Markov chain with mean sojourns τ_i: p_ii(Δt) = exp(−Δt/τ_i),
    the rest shared equally (eq M3)."""
    stay = np.exp(-dt[..., None] / tau)
    Pi = np.broadcast_to(((1.0 - stay) / 2)[..., :, None], (*dt.shape, 3, 3)).copy()
    idx = np.arange(3)
    Pi[..., idx, idx] = stay
    return Pi


AIRCRAFT_Q = (0.5, 0.05, 5.0)
"""Default psds of :func:`aircraft_models`: q̃₁ = 0.5 m²/s³ (CV: a velocity random walk of 0.7 m/s in 1 s,
an airliner's wind and autopilot corrections), q̃₂ = 0.05 m²/s⁵ and q̃₃ = 5 m²/s⁵ (Wiener-process
acceleration: a standard turn, 3°/s at 230 m/s, is 12 m/s² reached in a few seconds). Chosen by the
engineer, measured on real flights (see the notebook *Tracking a real flight*), not the paper's."""
AIRCRAFT_SOJOURN = (120.0, 20.0, 20.0)
"""Mean sojourn τ_i in each model [s] (eq M3): cruise legs last minutes, turns tens of seconds."""


def aircraft_models(
    q: tuple[float, float, float] = AIRCRAFT_Q,
    sojourn: tuple[float, float, float] = AIRCRAFT_SOJOURN,
    mu0: np.ndarray | tuple[float, ...] = (0.8, 0.1, 0.1),
    T: float = 1.0,
) -> ModelSet:
    """An IMM model set for real aircraft on irregular times (module docstring, eqs M1–M3): CV with white-noise
    acceleration (psd q̃₁ [m²/s³]) and two Wiener-process-acceleration models (psds q̃₂, q̃₃ [m²/s⁵]), every
    model with process noise (so no filter becomes singular), switching as a continuous-time Markov chain
    with mean sojourns τ_i [s].

    Args:
        q: (q̃₁, q̃₂, q̃₃), each > 0.
        sojourn: (τ₁, τ₂, τ₃) [s], each > 0.
        mu0: the model probabilities at the initialisation.
        T: the step of the returned ``Phi``, ``Qd`` and ``Pi`` (a nominal period [s]; ``steps`` gives any).

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli.models.motion import aircraft_models
        >>> ms = aircraft_models()
        >>> Phi, Qd, Pi = ms.steps(np.array([0.5, 2.0]))
        >>> Phi.shape, round(float(Pi[1, 0, 0]), 6)  # p_11(2 s) = exp(−2/120)
        ((2, 3, 6, 6), 0.983471)
    """
    _check_T(T)
    if len(q) != 3 or not all(math.isfinite(v) and v > 0 for v in q):
        raise ConfigError("q", tuple(q), "is not three finite psds > 0 (every model needs process noise)")
    if len(sojourn) != 3 or not all(math.isfinite(v) and v > 0 for v in sojourn):
        raise ConfigError("sojourn", tuple(sojourn), "is not three finite mean sojourn times > 0 [s]")
    tau = np.asarray(sojourn, float)

    def steps(dt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        dt = np.asarray(dt, float)
        Phi = np.stack([_phi_cv6(dt), _phi_ca6(dt), _phi_ca6(dt)], axis=-3)
        Qd = np.stack([_q_cv6(dt, q[0]), _q_ca6(dt, q[1]), _q_ca6(dt, q[2])], axis=-3)
        return Phi, Qd, _switching(dt, tau)

    Phi, Qd, Pi = steps(np.float64(T))
    return ModelSet(Phi, Qd, Pi, np.asarray(mu0, float),
                    names=("CV", f"CA q={q[1]:g}", f"CA q={q[2]:g}"), steps=steps)  # fmt: skip


CT_RATE_DEG_S = 3.0
"""The turn rate of :func:`coordinated_turn_models` [°/s]: the standard rate turn of civil aviation."""


def coordinated_turn_models(
    q: tuple[float, float, float] = (0.5, 2.0, 2.0),
    rate_deg_s: float = CT_RATE_DEG_S,
    sojourn: tuple[float, float, float] = AIRCRAFT_SOJOURN,
    mu0: np.ndarray | tuple[float, ...] = (0.8, 0.1, 0.1),
    T: float = 1.0,
) -> ModelSet:
    """An IMM model set with coordinated turns of a known rate (Bar-Shalom, Li & Kirubarajan 2001, §11.7.1):
    CV, a left and a right turn at ±ω, each with white-noise acceleration of psd q̃_j [m²/s³] (eq M1) and the
    switching of eq M3, on the IMM's 6-D state (acceleration rows zero). Per step Δt the turn is exact:

        [x, ẋ]' = [x + (sin ωΔt/ω) ẋ − ((1 − cos ωΔt)/ω) ẏ,  cos ωΔt ẋ − sin ωΔt ẏ],
        [y, ẏ]' = [y + ((1 − cos ωΔt)/ω) ẋ + (sin ωΔt/ω) ẏ,  sin ωΔt ẋ + cos ωΔt ẏ]          (CT)

    (ω > 0 counter-clockwise in the east/north plane). Offered beside :func:`aircraft_models` and measured on
    real flights (the notebook *Tracking a real flight*).
    """
    _check_T(T)
    if len(q) != 3 or not all(math.isfinite(v) and v > 0 for v in q):
        raise ConfigError("q", tuple(q), "is not three finite psds > 0")
    in_range("rate_deg_s", rate_deg_s, 1e-3, 90.0, unit="°/s")
    if len(sojourn) != 3 or not all(math.isfinite(v) and v > 0 for v in sojourn):
        raise ConfigError("sojourn", tuple(sojourn), "is not three finite mean sojourn times > 0 [s]")
    w = math.radians(rate_deg_s)
    tau = np.asarray(sojourn, float)

    def ct(dt: np.ndarray, omega: float) -> np.ndarray:
        P = _phi_cv6(dt)
        s, c = np.sin(omega * dt), np.cos(omega * dt)
        P[..., 0, 1], P[..., 0, 3] = s / omega, -(1 - c) / omega
        P[..., 1, 1], P[..., 1, 3] = c, -s
        P[..., 2, 1], P[..., 2, 3] = (1 - c) / omega, s / omega
        P[..., 3, 1], P[..., 3, 3] = s, c
        return P

    def steps(dt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        dt = np.asarray(dt, float)
        Phi = np.stack([_phi_cv6(dt), ct(dt, w), ct(dt, -w)], axis=-3)
        Qd = np.stack([_q_cv6(dt, q[0]), _q_cv6(dt, q[1]), _q_cv6(dt, q[2])], axis=-3)
        return Phi, Qd, _switching(dt, tau)

    Phi, Qd, Pi = steps(np.float64(T))
    return ModelSet(Phi, Qd, Pi, np.asarray(mu0, float),
                    names=("CV", f"CT +{rate_deg_s:g}°/s", f"CT −{rate_deg_s:g}°/s"), steps=steps)  # fmt: skip


def two_point_init(
    z1: np.ndarray, z2: np.ndarray, T: float, sigma: float, n: int = 6
) -> tuple[np.ndarray, np.ndarray]:
    """Two-point differencing initialisation at scan 2 (§IV).

    X̂(2|2) = [z_x(2), (z_x(2) − z_x(1))/T, z_y(2), (z_y(2) − z_y(1))/T, 0, 0] and
    P(2|2) = blockdiag over the axes of [[δ², δ²/T], [δ²/T, 2δ²/T²]] with δ = σ (the paper prints δ_x in the ẏ
    entry; fixed) and a zero acceleration block. ``n = 4`` gives the same for the state [x, ẋ, y, ẏ].

    Args:
        z1: (..., 2) measurements of scan 1 [m].
        z2: (..., 2) measurements of scan 2 [m].
        T: scan period [s].
        sigma: measurement noise σ per axis [m].
        n: state dimension, 6 (the IMM's) or 4.

    Returns:
        x (..., n) and P (n, n).

    Examples:
        >>> from motionsig_cli import two_point_init
        >>> x, P = two_point_init([0.0, 0.0], [10.0, 5.0], T=2.0, sigma=3.0, n=4)
        >>> x.tolist()  # [x, ẋ, y, ẏ]
        [10.0, 5.0, 5.0, 2.5]
        >>> P[:2, :2].tolist()  # [[σ², σ²/T], [σ²/T, 2σ²/T²]]
        [[9.0, 4.5], [4.5, 4.5]]
    """
    _check_T(T)
    one_of("n", n, (4, 6))
    z1, z2 = np.asarray(z1, float), np.asarray(z2, float)
    x = np.zeros((*np.broadcast_shapes(z1.shape, z2.shape)[:-1], n))
    x[..., 0] = z2[..., 0]
    x[..., 1] = (z2[..., 0] - z1[..., 0]) / T
    x[..., 2] = z2[..., 1]
    x[..., 3] = (z2[..., 1] - z1[..., 1]) / T
    d2 = sigma * sigma
    block = np.array([[d2, d2 / T], [d2 / T, 2 * d2 / T**2]])
    P = np.zeros((n, n))
    P[:2, :2] = block
    P[2:4, 2:4] = block
    return x, P


def two_point_restart(
    z_a: np.ndarray, z_b: np.ndarray, dt: np.ndarray, R_a: np.ndarray, R_b: np.ndarray, n: int = 6
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`two_point_init` for a batch of tracks with their own spacing and covariances — the restart of a
    tracker that lost consistency (:mod:`motionsig_cli.filters.consistency`).

    Args:
        z_a, z_b: (B, 2) the two measurements; dt: (B,) the time from z_a to z_b [s] (> 0).
        R_a, R_b: (B, 2, 2) their covariances.
        n: 6 (the IMM's state) or 4.

    Returns:
        x (B, n) = [z_b, (z_b − z_a)/Δt per axis, 0…] and P (B, n, n): position R_b, position–velocity
        R_b/Δt, velocity (R_a + R_b)/Δt², a zero acceleration block.
    """
    one_of("n", n, (4, 6))
    B = z_a.shape[0]
    x = np.zeros((B, n))
    v = (z_b - z_a) / dt[:, None]
    x[:, 0], x[:, 1], x[:, 2], x[:, 3] = z_b[:, 0], v[:, 0], z_b[:, 1], v[:, 1]
    P = np.zeros((B, n, n))
    pos, vel = [0, 2], [1, 3]
    d = dt[:, None, None]
    P[:, np.ix_(pos, pos)[0], np.ix_(pos, pos)[1]] = R_b
    P[:, np.ix_(pos, vel)[0], np.ix_(pos, vel)[1]] = R_b / d
    P[:, np.ix_(vel, pos)[0], np.ix_(vel, pos)[1]] = R_b / d
    P[:, np.ix_(vel, vel)[0], np.ix_(vel, vel)[1]] = (R_a + R_b) / (d * d)
    return x, P
