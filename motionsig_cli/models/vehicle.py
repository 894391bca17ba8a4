"""The 1-D closed-loop vehicle of the mode-signature paper (47th IEEE CDC, Cancún, 2008), §IV.A, eqs 53–55, and its augmented filter models (eq 44).

Truth::

    x_{k+1} = [[1, T], [0, 1]] x_k + [0, T]ᵀ u_k + [T²/2, T]ᵀ w_k          eq (53), w ~ N(0, σ_a²)
    u_k     = K (−x̄_k + r_k + a_sig [z_k, ż_k]ᵀ)                              controller, eqs (5), (54)
    y_k     = [1, 0] x_k + v_k,   v ~ N(0, R)                               eq (55)
    r_k     = [a_r sin(2π f_r t_k), 2π f_r a_r cos(2π f_r t_k)]ᵀ            nominal reference [A]
    z_k     = p_k[τ] cos(2π f_c t_k + 2π f_d t_k + θ)                       signature, eq (3)

x̄_k is the true state x_k (``feedback="true"``, the closed loop of eq 44) or the vehicle's own estimate
x̂_{k|k} (``feedback="estimate"``, eq 5: "the controller calculates the total control input as a function
of its vehicle state estimate"). The onboard estimator [A] is the time-varying Kalman filter of the plant
[x, ẋ] (eq 53 with the known input u_k and white acceleration noise σ_a) on the vehicle's own position
sensor y^own_k = x_k + v^own_k, v^own ~ N(0, R) independent of the observer's v_k (the same variance R),
started from the known initial state x_0 = 0 (P_{0|−1} = 0); u_k uses the filtered x̂_{k|k}, which has
seen y^own_k. f_d is the carrier offset of the received signature (eq 3, the paper's f_{d,k} multiplied by
t_k): the truth's carrier is f_c + f_d; the paper sets f_d = 0.

Filter models (eq 44 with true-state feedback, A_r a constant-velocity random walk)::

    state H0: [x, ẋ, r, ṙ];  H1: [x, ẋ, r, ṙ, a]
    F^{H1}_k = [[1, T, 0, 0, 0],
                [−T k1, 1 − T k2, T k1, T k2, T (k1 z_k + k2 ż_k)],
                [0, 0, 1, T, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1]]
    F^{H0} = upper-left 4×4 block;  H = [1, 0, 0, 0(, 0)]
    Q^{H0} = diag(1e-3, 1e2, 1e-1, 1e1) (eq 56);  Q^{H1} = diag(…, Q_a = 1) (eq 57, "10⁰")

With ``A_r = "known"`` the filters drop r, ṙ: state H0 [x, ẋ], H1 [x, ẋ, a] (the upper-left 2×2 plant
block, and the a-column), and the nominal reference enters as a known input
(:func:`reference_response`).

[A] = our assumption: the paper does not state it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of, positive

Q0_DIAG = (1e-3, 1e2, 1e-1, 1e1)  # eq (56), per step
QA_DEFAULT = 1.0  # eq (57) last entry, read as 10^0
DEFAULT_R = 1e-5  # the best ANR of Figs 4–6 (label 94.3)
# how an ANR in dB is read: log10, true decibels 10·log10(ANR) (the default); paper-ln, the mode-signature
# paper's "dB" labels, 10·ln(ANR) (94.3 ↔ R = 1e-5, 48.3 ↔ R = 1e-3 at a_sig = 0.5)
DB_CONVENTIONS = ("log10", "paper-ln")
FEEDBACKS = ("true", "estimate")
REFERENCE_MODELS = ("cv", "identity", "known")  # A_r of the filters (see transition_h0)
ONBOARD_ESTIMATOR = (
    "feedback on the vehicle's own estimate (eq 5): a time-varying Kalman filter of [x, xdot] (eq 53, "
    "known input u, white acceleration sigma_a) on the vehicle's own position sensor (noise variance R, "
    "independent of the observer's measurement y), x0 = 0 known; u_k uses the filtered estimate (assumed)"
)


def pole_placement_gain(T: float, wn: float = 4 * math.pi, zeta: float = 0.7) -> tuple[float, float]:
    """K = [k1, k2] placing the poles of A − BK at e^{sT}, s = −ζω_n ± jω_n√(1−ζ²) [A: ω_n = 4π rad/s,
    ζ = 0.7 by default].

    det(zI − (A − BK)) = z² + (T k2 − 2) z + (1 − T k2 + T² k1) = z² + α1 z + α0 with
    α1 = −2 e^{−ζω_nT} cos(ω_d T), α0 = e^{−2ζω_nT}  ⇒  k2 = (2 + α1)/T, k1 = (1 + α1 + α0)/T².

    Raises:
        ConfigError: T or wn not a finite number > 0, zeta not in (0, 1) (an underdamped pole pair),
            or T so small that T² underflows.
    """
    positive("T", T, unit="s")
    positive("wn", wn, unit="rad/s")
    in_range("zeta", zeta, 0.0, 1.0, lo_open=True, hi_open=True)
    if T**2 == 0:
        raise ConfigError("T", T, "is too small for pole placement (T² underflows)")
    wd = wn * math.sqrt(1 - zeta**2)
    a1 = -2 * math.exp(-zeta * wn * T) * math.cos(wd * T)
    a0 = math.exp(-2 * zeta * wn * T)
    return (1 + a1 + a0) / T**2, (2 + a1) / T


def check_gain(name: str, K: Any) -> None:
    """A feedback gain: two finite numbers (k1, k2), else :class:`ConfigError` naming ``name``."""
    ok = isinstance(K, Sequence) and len(K) == 2
    try:
        ok = ok and all(math.isfinite(float(k)) for k in K)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ConfigError(name, K, "is not two finite gains k1, k2")


def measurement_variance(
    R: float | None, anr_db: float | None, db_convention: str = "log10", a_sig: float = 0.5
) -> float:
    """The measurement-noise variance R given itself or an ANR in dB (ANR = a_sig²/(2R), eq 58).

    ``db_convention`` ``"log10"`` (the default) reads the dB value as true decibels, ANR = 10^(dB/10);
    ``"paper-ln"`` as the paper's labels of Figs 4–6, 10·ln(ANR), so ANR = e^(dB/10). Neither given:
    R = 1e-5. R itself is checked by :class:`Vehicle1D`.

    Raises:
        ConfigError: both given, an unknown convention, a_sig ≤ 0 with an ANR (no R gives it), or an ANR
            whose R is not a positive finite number.
    """
    one_of("db_convention", db_convention, DB_CONVENTIONS)
    if anr_db is None:
        return DEFAULT_R if R is None else R
    if R is not None:
        raise ConfigError("anr_db", anr_db, "is given together with the variance R: give one, not both")
    if not math.isfinite(anr_db):
        raise ConfigError("anr_db", anr_db, "is not a finite number")
    if not a_sig > 0:
        raise ConfigError("a_sig", a_sig, "is not > 0, so no measurement variance gives the ANR")
    try:
        anr = math.exp(anr_db / 10) if db_convention == "paper-ln" else 10 ** (anr_db / 10)
        R = a_sig**2 / (2 * anr)
    except OverflowError:
        raise ConfigError("anr_db", anr_db, "is too large: the measurement variance R underflows") from None
    except ZeroDivisionError:
        raise ConfigError("anr_db", anr_db, "is too small: the measurement variance R overflows") from None
    if not (math.isfinite(R) and R > 0):
        raise ConfigError(
            "anr_db", anr_db, f"gives a measurement variance R = {R:g}, not a finite number > 0"
        )
    return R


@dataclass(frozen=True, slots=True)
class ClosedLoop:
    """The closed-loop fields that the 1-D (:class:`Vehicle1D`) and 2-D
    (:class:`~motionsig_cli.models.vehicle2d.Vehicle2D`) examples share, first in both; each documents
    them. Checked here: T finite and > 0; a_sig, a_r, f_r and sigma_a finite and ≥ 0; K two finite gains.
    """

    T: float = 0.05
    K: tuple[float, float] = field(default_factory=lambda: pole_placement_gain(0.05))
    a_sig: float = 0.5
    a_r: float = 10.0
    f_r: float = 0.01
    sigma_a: float = 0.01

    def __post_init__(self) -> None:
        positive("T", self.T, unit="s")
        check_gain("K", self.K)
        for name in ("a_sig", "a_r", "f_r", "sigma_a"):
            in_range(name, getattr(self, name), 0.0)


@dataclass(frozen=True, slots=True)
class Vehicle1D(ClosedLoop):
    """Parameters of the 1-D example ([A] = our assumption: the paper does not state it).

    Checked here, once: T and R finite and > 0; a_sig, a_r, f_r and sigma_a finite and ≥ 0 (a zero
    amplitude, frequency or noise is a legitimate degenerate case: a_sig = 0 carries no signature);
    K two finite gains.

    Attributes:
        T: Sample interval [s] (assumed: 0.05 s).
        K: Feedback gain (k1, k2); default pole placement ω_n = 4π, ζ = 0.7 [A].
        a_sig: Signature amplitude (0.5 in the paper).
        a_r: Nominal reference amplitude (10 in the paper).
        f_r: Nominal reference frequency [Hz] (0.01, 0.1 or 1 in the paper).
        sigma_a: True white-acceleration noise [m/s²] (assumed: 0.01).
        R: Measurement-noise variance (1e-1 … 1e-5, derived from the paper's ANR labels).
        f_d: Carrier offset [Hz] of the received signature, finite (eq 3: cos(2π f_c t + 2π f_d t + θ));
            the simulator's carrier is f_c + f_d, which must be >= 0 (checked where f_c is known). The
            paper: 0.
        feedback: ``"true"`` (the controller on the true state, eq 44; the default) or ``"estimate"``
            (on the vehicle's own state estimate, eq 5; the onboard Kalman filter of the module
            docstring [A]).

    Raises:
        ConfigError: naming the first bad field.

    Examples:
        >>> from motionsig_cli import ConfigError, Vehicle1D
        >>> Vehicle1D().T
        0.05
        >>> try:
        ...     Vehicle1D(T=-1.0)
        ... except ConfigError as exc:
        ...     print(exc.field)
        T
    """

    R: float = DEFAULT_R
    f_d: float = 0.0
    feedback: Literal["true", "estimate"] = "true"

    def __post_init__(self) -> None:
        ClosedLoop.__post_init__(self)
        positive("R", self.R)
        in_range("f_d", self.f_d, -math.inf, unit="Hz")
        one_of("feedback", self.feedback, FEEDBACKS)

    @property
    def anr(self) -> float:
        """ANR = a_sig² / (2 R) (eq 58, scalar measurement)."""
        return self.a_sig**2 / (2 * self.R)


def nominal_reference(cfg: Vehicle1D, t: np.ndarray) -> np.ndarray:
    """r_k = [a_r sin(2π f_r t), 2π f_r a_r cos(2π f_r t)], shape (N, 2) [A: sine]."""
    w = 2 * np.pi * cfg.f_r
    return np.stack([cfg.a_r * np.sin(w * t), w * cfg.a_r * np.cos(w * t)], axis=-1)


def simulate_1d(
    cfg: Vehicle1D,
    z: np.ndarray,
    zdot: np.ndarray,
    w: np.ndarray,
    v: np.ndarray,
    v_own: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Closed-loop truth and measurements for a batch of records (eqs 53–55; eq 5 with
    ``cfg.feedback == "estimate"``).

    Args:
        cfg: Vehicle parameters.
        z: Signature, (B, N) (zero for "no signature"); the carrier offset f_d is
            the caller's (the replica at f_c + f_d, eq 3).
        zdot: Its derivative, (B, N).
        w: Standard-normal process-noise draws (B, N), scaled by σ_a here.
        v: Standard-normal measurement-noise draws (B, N), scaled by √R here.
        v_own: ``feedback="estimate"`` only (required then): standard-normal draws (B, N) of the vehicle's
            own position sensor, scaled by √R here.

    Returns:
        ``t`` (N,), ``x`` (B, N, 2) true state at each sample, ``u`` (B, N), ``y`` (B, N),
        ``r`` (N, 2) nominal reference; with ``feedback="estimate"`` also ``xhat`` (B, N, 2), the
        onboard filter's x̂_{k|k} the controller used.

    Examples:
        With no signature and no noise the closed loop stays at rest:

        >>> import numpy as np
        >>> from motionsig_cli import Vehicle1D, simulate_1d
        >>> zero = np.zeros((1, 100))
        >>> out = simulate_1d(Vehicle1D(sigma_a=0.0, a_r=0.0), zero, zero, zero, zero)
        >>> sorted(out), float(np.abs(out["y"]).max())
        (['r', 't', 'u', 'x', 'y'], 0.0)
    """
    z, zdot, w, v = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (z, zdot, w, v))
    B, N = z.shape
    T = cfg.T
    k1, k2 = cfg.K
    t = np.arange(N) * T
    r = nominal_reference(cfg, t)
    estimate = cfg.feedback == "estimate"
    if estimate:
        if v_own is None:
            raise ValueError("feedback='estimate' needs the onboard sensor's noise draws v_own")
        v_own = np.atleast_2d(np.asarray(v_own, dtype=float))
        if v_own.shape != (B, N):
            raise ValueError(f"v_own must be ({B}, {N}) like z")
        xhat = np.zeros((B, 2))  # x̂_{0|−1} = x_0 = 0, known exactly (P_{0|−1} = 0) [A]
        P = np.zeros((2, 2))
        A = np.array([[1.0, T], [0.0, 1.0]])
        G = np.array([0.5 * T**2, T])
        Qw = cfg.sigma_a**2 * np.outer(G, G)  # white acceleration, eq (53)
        xhats = np.empty((B, N, 2))
        sqrtR = math.sqrt(cfg.R)
    x = np.zeros((B, 2))
    xs = np.empty((B, N, 2))
    us = np.empty((B, N))
    for k in range(N):
        xs[:, k] = x
        fb = x
        if estimate:  # the onboard Kalman filter's update with the vehicle's own measurement [A]
            y_own = x[:, 0] + sqrtR * v_own[:, k]
            S = P[0, 0] + cfg.R
            gain = P[:, 0] / S
            xhat = xhat + gain[None, :] * (y_own - xhat[:, 0])[:, None]
            IKH = np.eye(2) - np.outer(gain, [1.0, 0.0])
            P = IKH @ P @ IKH.T + cfg.R * np.outer(gain, gain)  # Joseph form
            xhats[:, k] = xhat
            fb = xhat
        e_pos = -fb[:, 0] + r[k, 0] + cfg.a_sig * z[:, k]  # −x̄ + r + a_sig t_z(z), eqs (5), (54)
        e_vel = -fb[:, 1] + r[k, 1] + cfg.a_sig * zdot[:, k]
        u = k1 * e_pos + k2 * e_vel
        us[:, k] = u
        acc = cfg.sigma_a * w[:, k]
        x = np.stack(
            [x[:, 0] + T * x[:, 1] + 0.5 * T**2 * acc, x[:, 1] + T * u + T * acc], axis=-1
        )  # eq (53): A x + B u + [T²/2, T] w
        if estimate:  # prediction with the known input: x̂_{k+1|k} = A x̂_{k|k} + B u_k
            xhat = np.stack([xhat[:, 0] + T * xhat[:, 1], xhat[:, 1] + T * u], axis=-1)
            P = A @ P @ A.T + Qw
            P = 0.5 * (P + P.T)
    y = xs[:, :, 0] + math.sqrt(cfg.R) * v  # eq (55)
    out = {"t": t, "x": xs, "u": us, "y": y, "r": r}
    if estimate:
        out["xhat"] = xhats
    return out


def transition_h0(cfg: Vehicle1D, A_r: str = "cv") -> np.ndarray:
    """F^{H0} (eq 44 without the amplitude state), constant: 4×4 on [x, ẋ, r, ṙ] with the reference a
    constant-velocity (``"cv"``) or a static (``"identity"``) random walk; 2×2 on [x, ẋ] with ``"known"``
    (the reference a known input, :func:`reference_response`)."""
    one_of("A_r", A_r, REFERENCE_MODELS)
    T = cfg.T
    k1, k2 = cfg.K
    if A_r == "known":
        return np.array([[1.0, T], [-T * k1, 1 - T * k2]])  # A − B K, eqs (53)–(54)
    F = np.array(
        [
            [1.0, T, 0.0, 0.0],
            [-T * k1, 1 - T * k2, T * k1, T * k2],
            [0.0, 0.0, 1.0, T if A_r == "cv" else 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )
    return F


def reference_response(cfg: Vehicle1D, reference: np.ndarray) -> np.ndarray:
    """The position response H m_k of the filters' plant to a known nominal reference (``A_r="known"``).

    m_0 = 0, m_{k+1} = (A − BK) m_k + B K r_k = (A − BK) m_k + [0, T (k1 r_k + k2 ṙ_k)]ᵀ (eqs 53–54, the
    reference part of the control input). The model is linear and the amplitude state receives no input,
    so every filter of the bank (H0 and H1) sees the known input as this one deterministic response: its
    innovations on y equal those of the input-free model on y − H m (the filter's error dynamics do not
    involve the input).

    Args:
        cfg: The vehicle the filters assume (T, K).
        reference: [r_k, ṙ_k] at the samples, (N, 2) or per record (B, N, 2).

    Returns:
        H m_k, (N,) or (B, N).
    """
    ref = np.asarray(reference, dtype=float)
    T = cfg.T
    k1, k2 = cfg.K
    g = T * (k1 * ref[..., 0] + k2 * ref[..., 1])  # (…, N): the velocity row's input
    F = transition_h0(cfg, "known")
    pos = np.zeros(g.shape[:-1])
    vel = np.zeros(g.shape[:-1])
    out = np.empty(g.shape)
    for k in range(g.shape[-1]):
        out[..., k] = pos
        pos, vel = F[0, 0] * pos + F[0, 1] * vel, F[1, 0] * pos + F[1, 1] * vel + g[..., k]
    return out


def amplitude_column(cfg: Vehicle1D, z: np.ndarray, zdot: np.ndarray) -> np.ndarray:
    """The time-varying a-column entry T (k1 z_k + k2 ż_k) of F^{H1}_k (eq 44, row ẋ)."""
    k1, k2 = cfg.K
    return cfg.T * (k1 * np.asarray(z) + k2 * np.asarray(zdot))
