"""Jamming-vulnerability bounds of the air-to-satellite-to-ground surveillance link — Section 2 and
Appendices A–D of ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972).

N_T aircraft own one signature each; N = N/N_T·N_T of them are airborne and send it every α seconds
through S = 4 satellites. Per (aircraft, satellite) a matched filter sampled at 2B samples/s makes
binary decisions with probabilities p_d and p_f; a white-noise jammer of ERP J fills the band B.
Over K segments the processor declares an aircraft present iff more than K·t of its K arrival-time
lists are non-empty (A.11; the printed A.9–A.10 have the inequality reversed) and picks a position
at random among flight-consistent candidates. The report lower-bounds

    P_D ≥ P_DL = 1 − exp(−K · E(t, q)),  q = p_d^S,  E(t, q) = max_ν [ν(1−t) − ln((1−q)e^ν + q)]
                                                                           eqs 2.4.1–2.4.2, A.17–A.18
    p_f = Φ(Φ⁻¹(p_d) − d),  d = √(P₀Bτ/J)       (≡ ½ − ½ erf(√(P₀Bτ/2J) − φ))  eqs 2.7.1, D.17
    X(p_f) = [1 − (1−p_f)^{2Bα}] [1 − (1−p_f)^{4Bβ}]^{S−1}                   eq B.6
    Y(p_f) = [1 − (1−p_f)^{2Bα}] [1 − (1−p_f)^{(8B/3)vα/c}]^{S−1}            eq C.14
    N̄_FL  = (N_T − N) X^{Kt+1}                                              eqs 2.5.5, 2.8.3
    N̄_ADL = ½ N P_DL Y^{K−1} X                                             eqs 2.5.12, 2.7.3, 2.8.4

The maximum over ν (the Chernoff parameter, printed as "J" or "v") has the closed form of the binary
Kullback–Leibler divergence E(t, q) = D(t‖q) for 0 < t < q, −ln(1−q) for t = 0 and 0 for t ≥ q.

Everything is evaluated in the log domain: the bounds span hundreds of decades (N̄_ADL/N_T ≈
10⁻²²² at K = 10, x = −16 dB) and (1 − p_f)^{2·10⁷} must never be formed. All functions broadcast
over their array arguments; the outputs are normalised by N_T (fractions of the population).

A bad parameter is a :class:`~motionsig_cli.config.ConfigError` naming the field or argument. SciPy's
root finder is imported only by the functions that solve for a root (it costs more to import than the
rest of this module).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.special import log_ndtr, ndtri, ndtri_exp

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive

MPH = 0.44704  # m/s per mile per hour (exact)
C_MPH = 299_792_458.0 / MPH  # speed of light in mph (assumed: the exact c; the report does not say)
LOG_TINY = -745.0  # ln of the smallest positive double: below it p itself underflows

Quantity = Literal["nfl", "nadl"]
PfForm = Literal["d17", "report"]


@dataclass(frozen=True, slots=True)
class JammingSystem:
    """System constants of ATC-10 §2.7–2.8 ([R] stated in the report, [A] our assumption).

    Attributes:
        bandwidth_hz: B, signal and jammer bandwidth [R 10 MHz]; sampling at 2B samples/s.
        alpha_s: α, signature repetition period [R 1 s].
        beta_s: β, largest differential delay across the satellites [R 24 ms].
        vmax_mph: v, largest aircraft speed [R 600 mph] (enters N̄_ADL for K > 1 only).
        c_mph: speed of light in mph [A exact; 186 000 mi/s moves the K = 1000 ERP by −0.18 dB].
        energy_j: E = P₀τ, signature energy [R 10 mJ]; only E·B matters.
        airborne_frac: N/N_T, airborne fraction of the population [R 0.1].
        flight_factor: the (2/3) tightening of the flight-consistency window (C.6) [R].
        pick_factor: probability of a wrong pick among ≥ 2 candidates (2.5.10) [R 0.5].
        satellites: S, satellites relaying each signature [R 4].
        pf_form: ``"d17"`` (default: √(P₀Bτ/2J), App. D re-derived) or ``"report"``: the misprinted
            ½√(P₀Bτ/J) of eqs 2.8.1/2.8.3, which the report uses for N̄_FL with K > 1 only.

    Checked ranges: B, α, β, v, c and E finite and > 0 with v < c (no aircraft outruns the signal);
    N/N_T in the open (0, 1) (some aircraft airborne, some on the ground: both bounds need N and N_T − N);
    flight_factor and pick_factor in (0, 1] (a window tightening and a probability); S an integer ≥ 1.
    The sample counts :attr:`n_alpha`, :attr:`n_beta` and :attr:`n_v` must be finite and positive too.
    """

    bandwidth_hz: float = 1.0e7
    alpha_s: float = 1.0
    beta_s: float = 0.024
    vmax_mph: float = 600.0
    c_mph: float = C_MPH
    energy_j: float = 0.01
    airborne_frac: float = 0.1
    flight_factor: float = 2.0 / 3.0
    pick_factor: float = 0.5
    satellites: int = 4
    pf_form: PfForm = "d17"

    def __post_init__(self) -> None:
        for name, unit in (
            ("bandwidth_hz", "Hz"),
            ("alpha_s", "s"),
            ("beta_s", "s"),
            ("vmax_mph", "mph"),
            ("c_mph", "mph"),
            ("energy_j", "J"),
        ):
            positive(name, getattr(self, name), unit=unit)
        if not self.vmax_mph < self.c_mph:
            raise ConfigError(
                "vmax_mph", self.vmax_mph, f"is not below the speed of light ({self.c_mph:.6g} mph)"
            )
        in_range("airborne_frac", self.airborne_frac, 0.0, 1.0, lo_open=True, hi_open=True)
        in_range("flight_factor", self.flight_factor, 0.0, 1.0, lo_open=True)
        in_range("pick_factor", self.pick_factor, 0.0, 1.0, lo_open=True)
        integer("satellites", self.satellites, 1)
        one_of("pf_form", self.pf_form, ("d17", "report"))
        for name, formula in (("n_alpha", "2Bα"), ("n_beta", "4Bβ"), ("n_v", "(8B/3)vα/c")):
            n = getattr(self, name)
            if not (math.isfinite(n) and n > 0):
                raise ConfigError(name, n, f"is not a finite positive sample count ({name} = {formula})")

    @property
    def n_alpha(self) -> float:
        """Samples in one α-long sub-segment, 2Bα (B.6)."""
        return 2.0 * self.bandwidth_hz * self.alpha_s

    @property
    def n_beta(self) -> float:
        """Samples in a window of radius β, 4Bβ (B.6)."""
        return 4.0 * self.bandwidth_hz * self.beta_s

    @property
    def n_v(self) -> float:
        """Samples in a window of radius (2/3)vα/c: 2B·2·(2/3)vα/c = (8B/3)(vα/c) (C.14)."""
        return 4.0 * self.bandwidth_hz * self.flight_factor * self.vmax_mph * self.alpha_s / self.c_mph

    @property
    def eb_dbw(self) -> float:
        """10·log10(E·B) = 10·log10(P₀Bτ) in dBW: ERP[dBW] = x[dB] + eb_dbw (§2.8)."""
        return 10.0 * (math.log10(self.energy_j) + math.log10(self.bandwidth_hz))

    def pf_scale(self, quantity: Quantity, K: int) -> float:
        """Factor on d in p_f = Φ(z_d − scale·d): 1, or 1/√2 for the report's misprinted N̄_FL (K > 1)."""
        return math.sqrt(0.5) if (self.pf_form == "report" and quantity == "nfl" and K > 1) else 1.0


DEFAULT_SYSTEM = JammingSystem()


# --- stable elementary pieces ---------------------------------------------------------------------


def log1mexp(y: np.ndarray | float) -> np.ndarray:
    """ln(1 − e^y) for y ≤ 0, accurate for every y (Mächler 2012: expm1 near 0, log1p far away)."""
    y = np.asarray(y, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(y > -math.log(2.0), np.log(-np.expm1(y)), np.log1p(-np.exp(y)))


def log_window(log_p: np.ndarray | float, n: float) -> np.ndarray:
    """ln(1 − (1 − p)^n): the log probability that at least one of n samples fires (B.6, C.14).

    ``log_p`` is ln p, so probabilities far below the smallest double are handled. For n·p < 1e−8
    the series ln n + ln p − (n−1)p/2 (error O((np)²) ≤ 1e−16 relative) replaces ln(−expm1(·)).
    """
    log_p = np.asarray(log_p, dtype=float)
    p = np.exp(log_p)
    y = n * np.log1p(-np.minimum(p, 1.0))  # ln (1−p)^n ≤ 0
    small = -y < 1e-8
    with np.errstate(divide="ignore", invalid="ignore"):
        series = math.log(n) + log_p - 0.5 * (n - 1.0) * p
        exact = log1mexp(np.where(small, -1.0, y))
    return np.where(small, series, exact)


def amplitude_snr(x_db: np.ndarray | float) -> np.ndarray:
    """d = √(P₀Bτ/J) = 10^(−x/20), the matched-filter output amplitude SNR (App. D, D.7–D.9)."""
    return 10.0 ** (-np.asarray(x_db, dtype=float) / 20.0)


def log_pf(x_db: np.ndarray | float, p_d: np.ndarray | float, *, scale: float = 1.0) -> np.ndarray:
    """ln p_f for the Neyman–Pearson pulse detector at probability p_d and x = 10·log10(J/P₀Bτ).

    p_f = ½ − ½ erf(√(P₀Bτ/(2J)) − φ) with p_d = ½ + ½ erf(φ)          eqs 2.7.1–2.7.2, D.16–D.17
        = Φ(z_d − d),   z_d = Φ⁻¹(p_d) = √2 φ,   d = 10^(−x/20)
    ``scale = 1/√2`` gives the misprinted form ½√(P₀Bτ/J) of eqs 2.8.1/2.8.3 (jammer power doubled).
    """
    p_d = np.asarray(p_d, dtype=float)
    return log_ndtr(ndtri(p_d) - scale * amplitude_snr(x_db))  # eq D.17


# --- the first-stage decision: P_DL and its inversion (App. A) --------------------------------------


def _log1pmx(x: np.ndarray) -> np.ndarray:
    """ln(1 + x) − x, without cancellation for small |x| (Taylor series to x²⁰ for |x| < 0.1)."""
    x = np.asarray(x, dtype=float)
    small = np.abs(x) < 0.1
    xs = np.where(small, x, 0.0)
    acc = np.zeros_like(xs)
    for k in range(20, 1, -1):  # Horner: Σ_{k≥2} (−1)^{k+1} x^k / k
        acc = acc * xs + (-1.0) ** (k + 1) / k
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(small, acc * xs * xs, np.log1p(x) - x)


def detection_exponent(q: np.ndarray | float, t: np.ndarray | float) -> np.ndarray:
    """E(t, q) = max_{ν ≥ 0} [ν(1−t) − ln((1−q)e^ν + q)] in closed form (A.17–A.18).

    Setting the derivative to zero gives e^ν* = q(1−t)/(t(1−q)), admissible iff t ≤ q; the maximum is
    the binary Kullback–Leibler divergence D(t‖q) = t ln(t/q) + (1−t) ln((1−t)/(1−q)). At t = 0 the
    supremum (ν → ∞) is −ln(1−q); for t ≥ q the maximum is at ν = 0 and E = 0; for q = 1, E = ∞.

    When q is close to t (large K), the two terms cancel to first order; there D is evaluated as
    −t·[ln(1+a) − a] − (1−t)·[ln(1+b) − b] with a = (q−t)/t, b = (t−q)/(1−t), since t·a + (1−t)·b = 0.
    """
    q, t = np.broadcast_arrays(np.asarray(q, dtype=float), np.asarray(t, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        log1mq = np.log1p(-q)
        direct = np.where(t > 0, t * (np.log(t) - np.log(q)), 0.0) + (1.0 - t) * (np.log1p(-t) - log1mq)
        a = np.where(t > 0, (q - t) / np.where(t > 0, t, 1.0), np.inf)
        b = (t - q) / (1.0 - t)
        near = (np.abs(a) < 0.1) & (np.abs(b) < 0.1)
        series = -t * _log1pmx(np.where(near, a, 0.0)) - (1.0 - t) * _log1pmx(np.where(near, b, 0.0))
        kl = np.where(near, series, direct)  # D(t‖q)
        out = np.where(t >= q, 0.0, np.where(q >= 1.0, np.inf, kl))
    return np.asarray(out, dtype=float)


def chernoff_nu(q: np.ndarray | float, t: np.ndarray | float) -> np.ndarray:
    """The maximising Chernoff parameter ν* = ln[q(1−t)/(t(1−q))] (∞ at t = 0, 0 for t ≥ q)."""
    q, t = np.broadcast_arrays(np.asarray(q, dtype=float), np.asarray(t, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        nu = np.log(q) + np.log1p(-t) - np.log(t) - np.log1p(-q)
    return np.asarray(np.where(t >= q, 0.0, np.where(t <= 0, np.inf, nu)), dtype=float)


def p_dl(p_d: np.ndarray | float, K: int, t: np.ndarray | float = 0.0, *, satellites: int = 4) -> np.ndarray:
    """Lower bound on the aircraft detection probability (eqs 2.4.1, 2.4.2; A.10a, A.17, A.18).

    K = 1: P_DL = p_d^S. K > 1: P_DL = 1 − exp(−K·E(t, p_d^S)); t = 0 gives 1 − (1 − p_d^S)^K exactly.
    """
    q = np.asarray(p_d, dtype=float) ** satellites  # A.16: P(all S channels detect) ≈ p_d^S
    if K == 1:
        return q  # eq 2.4.1
    return -np.expm1(-K * detection_exponent(q, t))  # eq 2.4.2


def _check_design(K: int, t: float) -> None:
    integer("K", K, 1)
    in_range("t", t, 0.0, 1.0, hi_open=True)
    if K == 1 and t != 0.0:
        raise ConfigError(
            "t",
            t,
            "is not 0: with K = 1 the only meaningful rule is t = 0 (declare present iff the list is non-empty)",
        )


def p_d_for(K: int, pdl: float, t: float = 0.0, *, satellites: int = 4) -> float:
    """Invert P_DL(p_d, K, t) = pdl for the pulse detection probability p_d (eqs 2.4.1, 2.4.2).

    Closed forms for K = 1 and t = 0; otherwise K·D(t‖q) = −ln(1 − P_DL) is solved for q ∈ (t, 1)
    by Brent on w = ln(1 − q), which keeps resolution when q is within 1e−5 of 1. The result is checked
    by evaluating P_DL again; a target that double precision cannot meet is a ConfigError on ``pdl``.
    """
    _check_design(K, t)
    in_range("pdl", pdl, 0.0, 1.0, lo_open=True, hi_open=True)
    L = -math.log1p(-pdl)
    if K == 1:
        q = pdl  # eq 2.4.1
    elif t == 0.0:
        q = -math.expm1(-L / K)  # 1 − (1 − P_DL)^{1/K}
    else:
        from motionsig_cli.roots import brentq

        def gap(w: float) -> float:
            q_ = -math.expm1(w)
            return K * float(detection_exponent(q_, t)) - L

        w_hi = math.log1p(-t) - 1e-15
        if gap(w_hi) >= 0.0:
            raise ConfigError(
                "pdl",
                pdl,
                f"at K = {K} needs q = p_d^S within double precision of t = {t:g}; use a smaller K or t = 0",
            )
        if gap(-700.0) <= 0.0:
            raise ConfigError("pdl", pdl, f"with t = {t:g} needs p_d = 1 to double precision")
        q = -math.expm1(brentq(gap, -700.0, w_hi, xtol=1e-15, rtol=4 * np.finfo(float).eps))
    p_d = q ** (1.0 / satellites)
    if not 0.0 < p_d < 1.0:
        raise ConfigError(
            "pdl", pdl, f"at K = {K}, t = {t:g} needs p_d = {p_d:g} (not in (0, 1) in double precision)"
        )
    achieved = float(p_dl(p_d, K, t, satellites=satellites))
    if not abs(achieved - pdl) <= 1e-9 * pdl:
        raise ConfigError(
            "pdl",
            pdl,
            f"at K = {K}, t = {t:g} cannot be met in double precision (the nearest p_d gives {achieved:.10g})",
        )
    return p_d


def t_for(K: int, p_d: float, pdl: float, *, satellites: int = 4) -> float:
    """The rule parameter t ∈ [0, q) that gives P_DL = pdl at pulse probability p_d (eq 2.4.2 solved
    for t).

    Raises a ConfigError on ``pdl`` when even t = 0 falls short (1 − (1 − p_d^S)^K < P_DL).
    """
    from motionsig_cli.roots import brentq

    _check_design(K, 0.0)
    if K == 1:
        raise ConfigError(
            "pdl", pdl, "cannot be met by a choice of t with K = 1: P_DL = p_d^S is fixed and t must be 0"
        )
    in_range("p_d", p_d, 0.0, 1.0, lo_open=True, hi_open=True)
    in_range("pdl", pdl, 0.0, 1.0, lo_open=True, hi_open=True)
    q = p_d**satellites
    L = -math.log1p(-pdl)
    best = K * float(detection_exponent(q, 0.0))
    if best < L:
        raise ConfigError(
            "pdl", pdl, f"is infeasible at p_d = {p_d:g}: even t = 0 gives P_DL = {-math.expm1(-best):.6g}"
        )
    return brentq(lambda t: K * float(detection_exponent(q, t)) - L, 0.0, q, xtol=1e-15)


# --- the false-alarm and ambiguous-detection bounds (Apps B, C; §2.5) -----------------------------


def log_x(lpf: np.ndarray | float, system: JammingSystem) -> np.ndarray:
    """ln X(p_f): one list non-empty by false alarms alone (B.6)."""
    return log_window(lpf, system.n_alpha) + (system.satellites - 1) * log_window(lpf, system.n_beta)


def log_y(lpf: np.ndarray | float, system: JammingSystem) -> np.ndarray:
    """ln Y(p_f): a flight-consistent continuation by false alarms alone (C.14)."""
    return log_window(lpf, system.n_alpha) + (system.satellites - 1) * log_window(lpf, system.n_v)


def log_nfl_pf(lpf: np.ndarray | float, K: int, t: float, system: JammingSystem) -> np.ndarray:
    """ln(N̄_FL/N_T) = ln(1 − N/N_T) + (Kt + 1) ln X(p_f), real exponent Kt + 1 (2.5.5, B.11)."""
    return math.log1p(-system.airborne_frac) + (K * t + 1.0) * log_x(lpf, system)


def log_nadl_pf(lpf: np.ndarray | float, K: int, pdl: float, system: JammingSystem) -> np.ndarray:
    """ln(N̄_ADL/N_T) = ln(½ (N/N_T) P_DL) + (K−1) ln Y(p_f) + ln X(p_f) (2.5.12, 2.7.3, 2.8.4).

    For K = 1, P_DL = p_d^S and the Y factor vanishes, which is the K = 1 form of eq 2.7.3.
    """
    head = math.log(system.pick_factor * system.airborne_frac * pdl)
    body = log_x(lpf, system)
    if K > 1:
        body = body + (K - 1) * log_y(lpf, system)
    return head + body


@dataclass(frozen=True, slots=True)
class JammingDesign:
    """A processor design (K, p_d, t) with its detection bound P_DL (eqs 2.4.1–2.4.2).

    Attributes:
        K: Tracking length in pulses, an integer ≥ 1.
        p_d: Pulse detection probability in (0, 1), with q = p_d^S representable.
        t: Rule parameter in [0, 1): declare present iff more than K·t lists are non-empty (A.11); 0 when
            K = 1.
        satellites: S, an integer ≥ 1 (the system's S, 4 in the report).
    """

    K: int
    p_d: float
    t: float = 0.0
    satellites: int = 4

    def __post_init__(self) -> None:
        _check_design(self.K, self.t)
        integer("satellites", self.satellites, 1)
        in_range("p_d", self.p_d, 0.0, 1.0, lo_open=True, hi_open=True)
        if not self.p_d**self.satellites > 0.0:
            raise ConfigError("p_d", self.p_d, f"is so small that q = p_d^{self.satellites} underflows")

    @classmethod
    def from_pdl(cls, K: int, pdl: float, t: float = 0.0, *, satellites: int = 4) -> JammingDesign:
        """The design that meets P_DL = pdl with rule parameter t."""
        return cls(K, p_d_for(K, pdl, t, satellites=satellites), t, satellites)

    @property
    def q(self) -> float:
        """q = p_d^S, the probability that every satellite channel detects the true pulse (A.16)."""
        return self.p_d**self.satellites

    @property
    def pdl(self) -> float:
        """P_DL(p_d, K, t)."""
        return float(p_dl(self.p_d, self.K, self.t, satellites=self.satellites))

    @property
    def exponent(self) -> float:
        """E(t, q), the Chernoff exponent per segment (−ln(1 − q) at t = 0)."""
        return float(detection_exponent(self.q, self.t))

    @property
    def nu(self) -> float:
        """The maximising Chernoff parameter ν*."""
        return float(chernoff_nu(self.q, self.t))


def log_bound_pf(
    quantity: Quantity, lpf: np.ndarray | float, design: JammingDesign, system: JammingSystem
) -> np.ndarray:
    """ln(N̄/N_T) of ``quantity`` (``"nfl"`` or ``"nadl"``) as a function of ln p_f."""
    if design.satellites != system.satellites:
        raise ConfigError(
            "satellites", design.satellites, f"(the design's) is not the system's {system.satellites}"
        )
    one_of("quantity", quantity, ("nfl", "nadl"))
    if quantity == "nfl":
        return log_nfl_pf(lpf, design.K, design.t, system)
    return log_nadl_pf(lpf, design.K, design.pdl, system)


def log_bound(
    quantity: Quantity, x_db: np.ndarray | float, design: JammingDesign, system: JammingSystem
) -> np.ndarray:
    """ln(N̄_FL/N_T) or ln(N̄_ADL/N_T) at x = 10·log10(J/(P₀Bτ)) (eqs 2.7.3, 2.8.3, 2.8.4)."""
    lpf = log_pf(x_db, design.p_d, scale=system.pf_scale(quantity, design.K))
    return log_bound_pf(quantity, lpf, design, system)


def log_supremum(quantity: Quantity, design: JammingDesign, system: JammingSystem) -> float:
    """ln of the bound's supremum, reached as J → ∞ where p_f → p_d (eqs 2.5.5, 2.5.12 at p_f = p_d)."""
    return float(log_bound_pf(quantity, math.log(design.p_d), design, system))


@dataclass(frozen=True, slots=True)
class Threshold:
    """The jammer level at which a bound reaches a target (:func:`required_jamming`).

    Attributes:
        attainable: False when the target is at or above the bound's supremum (no jammer power
            reaches it; the report's "> 130 dBW").
        x_db: x* = 10·log10(J/(P₀Bτ)) (∞ when unattainable).
        erp_dbw: J* in dBW = x* + 10·log10(E·B).
        log_pf: ln p_f* at the threshold.
        d: d* = √(P₀Bτ/J*).
        log_sup: ln of the supremum of the bound (fraction of N_T).
        pf_over_pd: p_f*/p_d; above 0.9 the answer is ill-conditioned (d* is a small difference).
        dlog_per_db: d ln(N̄)/dx at x*: the relative change of the bound per dB.
    """

    attainable: bool
    x_db: float
    erp_dbw: float
    log_pf: float
    d: float
    log_sup: float
    pf_over_pd: float
    dlog_per_db: float

    @property
    def ill_conditioned(self) -> bool:
        """True when p_f* is within 10 % of its ceiling p_d (K = 1000 in the report), or when the bound
        changes by less than 0.1 % per dB at x* (the level sits on the plateau: a 1 % change of the
        level moves x* by more than 10 dB)."""
        return self.attainable and (self.pf_over_pd > 0.9 or abs(self.dlog_per_db) < 1e-3)


def check_level(quantity: Quantity, level: float, system: JammingSystem) -> None:
    """A target level of ``quantity`` is a fraction of N_T in (0, 1]; an N̄_FL level must also be below
    the bound's supremum N_T − N (a ConfigError on ``level`` otherwise)."""
    in_range("level", level, 0.0, 1.0, lo_open=True)
    if quantity == "nfl" and level >= 1.0 - system.airborne_frac:
        raise ConfigError(
            "level",
            level,
            f"is not below the N̄_FL supremum N_T − N = {1.0 - system.airborne_frac:g} N_T "
            "(the report's 0.9 N_T is that supremum)",
        )


def required_jamming(
    quantity: Quantity, level: float, design: JammingDesign, system: JammingSystem
) -> Threshold:
    """Solve N̄(x)/N_T = level for x: two-stage, in u = ln p_f (the inversion of eqs 2.7.3, 2.8.3, 2.8.4).

    1. The supremum S = bound(p_f = p_d); level ≥ S is unattainable.
    2. Brent on g(u) = ln bound(u) − ln level over u ∈ [u_lo, ln p_d] (g increases in u).
    3. d* = (Φ⁻¹(p_d) − Φ⁻¹(p_f*))/scale, x* = −20·log10 d*, ERP = x* + 10·log10(E·B).

    The level is checked by :func:`check_level`.
    """
    from motionsig_cli.roots import brentq

    check_level(quantity, level, system)
    log_level = math.log(level)
    log_sup = log_supremum(quantity, design, system)
    u_hi = math.log(design.p_d)
    if log_level >= log_sup:
        inf = math.inf
        return Threshold(False, inf, inf, u_hi, 0.0, log_sup, 1.0, 0.0)

    def g(u: float) -> float:
        return float(log_bound_pf(quantity, u, design, system)) - log_level

    u_lo = -50.0
    while g(u_lo) >= 0.0:  # the bound falls like (S·p_f^S) as p_f → 0, so this ends quickly
        u_lo *= 2.0
    u = brentq(g, u_lo, u_hi, xtol=1e-13, rtol=4 * np.finfo(float).eps, maxiter=500)
    scale = system.pf_scale(quantity, design.K)
    d = (float(ndtri(design.p_d)) - float(ndtri_exp(u))) / scale  # p_f = Φ(z_d − scale·d)
    if not d > 0.0:  # the level is within rounding of the supremum: no finite jammer power resolves it
        return Threshold(False, math.inf, math.inf, u_hi, 0.0, log_sup, 1.0, 0.0)
    x = -20.0 * math.log10(d)
    h = 1e-3
    slope = float(
        (log_bound(quantity, x + h, design, system) - log_bound(quantity, x - h, design, system)) / (2 * h)
    )
    return Threshold(True, x, x + system.eb_dbw, u, d, log_sup, math.exp(u) / design.p_d, slope)
