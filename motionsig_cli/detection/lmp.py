"""Locally most powerful (LMP) mode detector evaluated with Kalman-filter innovations — eqs (27)–(52) of
the mode-signature paper (47th IEEE CDC, Cancún, 2008).

For every candidate c = (i, τ, f_c) two filters run on the augmented model of eq (44): KF_cos with
the replica z_cos and KF_sin with z_sin; one H0 filter runs without the amplitude state. With
J := ½ Σ ν_jᵀ S_j⁻¹ ν_j (the innovation part of the negative log-likelihood, eqs 48–51),

    Λ(c) = 2 J_{H0} − J^c_{H1,cos} − J^c_{H1,sin}                                 eq (52)
    (î, τ̂, f̂_c) = argmax_c Λ(c),  λ* = max_c Λ(c)                               eqs (28)–(29)

``center="h0-noise"`` (our extension, not in the paper) subtracts E[Λ(c)] under white measurement
noise of the true variance R, computed exactly by a Lyapunov recursion. Under H0 the paper's
statistic has a candidate-dependent mean (each H1 filter's extra amplitude state absorbs a
different share of the noise), which biases the argmax towards mode 3 and a few code phases when
no signature is present. Centring makes the code-phase choice uniform and shrinks the mode bias
several-fold at unchanged detection power; it does not make the mode choice uniform (the
candidates' statistics are correlated differently, so their maxima are not exchangeable).

The filters' model (:func:`filter_model`): ``A_r`` ``"cv"`` or ``"identity"`` keeps the nominal reference
as a random-walk state [x, ẋ, r, ṙ(, a)] (eq 44); ``"known"`` drops r, ṙ ([x, ẋ(, a)]) and subtracts the
known reference's deterministic response from y before the bank
(:func:`~motionsig_cli.models.vehicle.reference_response`; exact, the model being linear). ``q_model``
``"per-step"`` reads Q0 and Q_a as per-step covariances (eqs 56–57); ``"continuous"`` as continuous-time
densities discretised over T by Van Loan's method (:func:`discretised_noise`).

``include_logdet`` adds ½ Σ log det(2πS) to every J (the full negative log-likelihood);
``weights="exact"`` multiplies the two gains J_{H0} − J_cos and J_{H0} − J_sin by c_cos and c_sin
(eqs 38, 40), with c = Σ_k z_k² / (c_r R) over the horizon, instead of dropping them as eq (42) does.

Missing samples (NaN in ``y``; for the radar a whole [range, bearing] row) are predict-only steps of
every filter of a bank: no update and no term in any J, the covariances propagated. Λ then compares the
likelihoods of the samples that are present (the exact prediction-error decomposition over them). The
Kalman bank runs one Riccati recursion per missing pattern among the records; the sigma-point bank
masks per record and step. The FFT path (:mod:`motionsig_cli.detection.lmp_fft`) cannot skip a sample.

Every configuration checks its own fields and raises :class:`~motionsig_cli.config.ConfigError` naming
the field.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.linalg

from motionsig_cli import cache
from motionsig_cli.cache import BytesLRU
from motionsig_cli.config import ConfigError, in_range, one_of, positive
from motionsig_cli.filters.kalman import (
    BankGains,
    Progress,
    expected_costs_white_noise,
    innovation_costs,
    missing_patterns,
    missing_steps,
    riccati,
    shared_progress,
)
from motionsig_cli.filters.kalman import MissingSamples as MissingSamples  # re-exported for the callers
from motionsig_cli.filters.unscented import (
    BankCosts,
    SigmaMeasurement,
    SigmaPointParams,
    StructuredTransition,
    linear_measurement,
    ukf_bank_costs,
)
from motionsig_cli.models.vehicle import (
    Q0_DIAG,
    QA_DEFAULT,
    REFERENCE_MODELS,
    Vehicle1D,
    amplitude_column,
    nominal_reference,
    reference_response,
    transition_h0,
)
from motionsig_cli.models.vehicle2d import (
    AMPLITUDE_ENTRIES_2D,
    Q0_2D,
    Q1_2D,
    Vehicle2D,
    prior_mean_2d,
    transition_h0_2d,
    transition_h1_2d_base,
)
from motionsig_cli.signals.signature import replica_bank

TAU_GRIDS = ("chips", "samples")
ZDOTS = ("analytic", "finite-difference")
Q_MODELS = ("per-step", "continuous")


def check_variances(field_name: str, values: tuple[float, ...], n: int, what: str) -> None:
    """``values`` are ``n`` finite process-noise variances >= 0 (Q = diag(values) must be positive
    semi-definite); ``what`` names the states, for the message."""
    if not isinstance(values, tuple | list) or len(values) != n:
        raise ConfigError(field_name, values, f"is not {n} variances for {what}")
    if not all(_variance_ok(v) for v in values):
        raise ConfigError(
            field_name,
            values,
            "holds a variance that is not finite and >= 0 (Q must be PSD, positive semi-definite)",
        )


def check_variance(field_name: str, value: float) -> None:
    """A finite process-noise variance >= 0 (Q must be positive semi-definite, PSD)."""
    if not _variance_ok(value):
        raise ConfigError(
            field_name, value, "is not a finite variance >= 0 (Q must be PSD, positive semi-definite)"
        )


def _variance_ok(value: float) -> bool:
    return (
        isinstance(value, numbers.Real)
        and not isinstance(value, bool)
        and math.isfinite(value)
        and value >= 0
    )


def check_grid(tau_grid: str, fc_grid: tuple[float, ...], include_logdet: bool, zdot: str) -> None:
    """The search grid and the options :class:`LMPConfig` and :class:`RadarLMPConfig` share."""
    one_of("tau_grid", tau_grid, TAU_GRIDS)
    if not isinstance(fc_grid, tuple | list) or not fc_grid:
        raise ConfigError("fc_grid", fc_grid, "holds no candidate carrier frequency")
    for f in fc_grid:
        in_range("fc_grid", f, 0.0, unit="Hz")
    one_of("include_logdet", include_logdet, (False, True))
    one_of("zdot", zdot, ZDOTS)


@dataclass(frozen=True, slots=True)
class LMPConfig:
    """Detector settings of the 1-D example.

    Attributes:
        c_r: KF measurement covariance R_KF = c_r · R (the paper uses c_r = 1 and 100, and calls 100 the
            "best trade-off").
        Q0: Per-step process noise of [x, ẋ, r, ṙ] (eq 56), finite and >= 0.
        Q_a: Per-step process noise of the amplitude state (eq 57, "10⁰" read as 1), finite and >= 0.
        P0: Prior covariance scale, identity × P0 (assumed: P0 = 1; the paper does not state it).
        A_r: The nominal reference in the filters: a random walk, ``"cv"`` (constant velocity) or
            ``"identity"`` (assumed: cv; the paper does not state it), or ``"known"``: the vehicle's own
            commanded reference, known in a cooperative setting, enters as a deterministic input and the
            filters drop r, ṙ (Q0's r, ṙ entries are then unused). The detector is given the reference
            (a_r, f_r of the vehicle it assumes, or the reference itself: :func:`lmp_detect`).
        tau_grid: ``"chips"`` (n_ρ chip-aligned phases) or ``"samples"`` (all n_ρ m_ρ phases).
        fc_grid: Candidate carrier frequencies [Hz], each finite and >= 0 (the paper: f_c known, one
            value).
        include_logdet: Add ½ Σ log det(2πS) (full negative log-likelihood).
        weights: ``"paper"`` (eq 42) or ``"exact"`` (eqs 38/40 weights c_cos, c_sin).
        zdot: Replica derivative, ``"analytic"`` or ``"finite-difference"``.
        center: ``"none"`` (eq 52) or ``"h0-noise"`` (our extension: E[Λ] under white noise subtracted).
        q_model: How Q0 and Q_a are read: ``"per-step"`` (the default: covariances of one step, eqs 56–57)
            or ``"continuous"`` (continuous-time densities, [unit²/s], discretised over T by Van Loan's
            method for the model's F: :func:`discretised_noise`).

    Examples:
        >>> from motionsig_cli import ConfigError, LMPConfig
        >>> LMPConfig().c_r
        100.0
        >>> try:
        ...     LMPConfig(c_r=0.0)
        ... except ConfigError as exc:
        ...     print(exc.field, exc.value)
        c_r 0.0
    """

    c_r: float = 100.0
    Q0: tuple[float, float, float, float] = Q0_DIAG
    Q_a: float = QA_DEFAULT
    P0: float = 1.0
    A_r: Literal["cv", "identity"] = "cv"
    tau_grid: Literal["chips", "samples"] = "chips"
    fc_grid: tuple[float, ...] = (1.0,)
    include_logdet: bool = False
    weights: Literal["paper", "exact"] = "paper"
    zdot: Literal["analytic", "finite-difference"] = "analytic"
    center: Literal["none", "h0-noise"] = "none"
    q_model: Literal["per-step", "continuous"] = "per-step"

    def __post_init__(self) -> None:
        positive("c_r", self.c_r)
        check_variances("Q0", self.Q0, 4, "[x, xdot, r, rdot] (eq 56)")
        check_variance("Q_a", self.Q_a)
        positive("P0", self.P0)
        one_of("A_r", self.A_r, REFERENCE_MODELS)
        one_of("q_model", self.q_model, Q_MODELS)
        check_grid(self.tau_grid, self.fc_grid, self.include_logdet, self.zdot)
        one_of("weights", self.weights, ("paper", "exact"))
        one_of("center", self.center, ("none", "h0-noise"))


def continuous_generator(F: np.ndarray, T: float) -> np.ndarray:
    """The real matrix A with e^{AT} = F (the principal logarithm, A = log(F)/T): the continuous-time model
    whose exact discretisation over T is the filters' F.

    For the default gain (pole placement at e^{sT}) the plant block's eigenvalues are the designed
    continuous poles s; the reference blocks (cv: [[0, 1], [0, 0]]; identity: 0) are exact.

    Raises:
        ConfigError: naming ``q_model``: F has an eigenvalue on the closed negative real axis (no real
            logarithm: T·K too large for a continuous-time reading).
    """
    eig = np.linalg.eigvals(F)
    if np.any((np.abs(eig.imag) <= 1e-12 * np.abs(eig)) & (eig.real <= 0)):
        raise ConfigError(
            "q_model", "continuous", "needs a transition F without eigenvalues <= 0 on the real axis (no real "
            f"continuous-time generator at T = {T:g} s with this gain): use per-step",
        )  # fmt: skip
    L = scipy.linalg.logm(F)
    if np.iscomplexobj(L):
        if np.max(np.abs(L.imag)) > 1e-9 * max(1.0, float(np.max(np.abs(L.real)))):
            raise ConfigError("q_model", "continuous", "found no real continuous-time generator of F")
        L = L.real
    return np.asarray(L, dtype=float) / T


def van_loan(A: np.ndarray, Qc: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    """(Φ, Q_d) = (e^{AT}, ∫₀ᵀ e^{As} Q_c e^{Aᵀs} ds) by Van Loan's method (C. F. Van Loan, Computing
    integrals involving the matrix exponential, IEEE Trans. Autom. Control 23(3), 1978):
    expm([[−A, Q_c], [0, Aᵀ]] T) = [[·, Φ⁻¹Q_d], [0, Φᵀ]], so Φ = (lower-right)ᵀ and Q_d = Φ (upper-right).
    Q_d is returned symmetrised."""
    n = A.shape[0]
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n] = -A
    M[:n, n:] = Qc
    M[n:, n:] = A.T
    E = scipy.linalg.expm(M * T)
    Phi = E[n:, n:].T
    Qd = Phi @ E[:n, n:]
    return Phi, 0.5 * (Qd + Qd.T)


def discretised_noise(F: np.ndarray, q: Sequence[float], T: float) -> np.ndarray:
    """Per-step process noise of densities ``q`` (diagonal Q_c) for the transition F over T: Van Loan with
    the generator A = log(F)/T (:func:`continuous_generator`), so e^{AT} = F exactly and
    Q_d = ∫₀ᵀ e^{As} Q_c e^{Aᵀs} ds. For small T, Q_d = Q_c T + O(T²)."""
    _, Qd = van_loan(continuous_generator(F, T), np.diag(np.asarray(q, dtype=float)), T)
    return Qd


@dataclass(frozen=True)
class FilterModel:
    """The 1-D filters' linear model (eq 44) for a vehicle and :class:`LMPConfig`: the H0 transition and
    process noise (n = 4 states [x, ẋ, r, ṙ], or 2 [x, ẋ] with ``A_r="known"``) and the amplitude's
    per-step variance; the H1 filters append the amplitude state (its time-varying a-column in the ẋ row).

    With ``q_model="continuous"`` the H0 noise is Van Loan's discretisation for F0 (exact for F0); the
    amplitude state's density Q_a becomes Q_a T (its own transition is 1). The a-column of eq 44 (a
    different one for every candidate and step) is left out of the noise integral, so one Q serves every
    H1 filter: an approximation of relative order T·|k1 z + k2 ż| in the amplitude-velocity terms.
    """

    F0: np.ndarray
    Q0: np.ndarray
    Q_a: float

    @property
    def n(self) -> int:
        """H0 states."""
        return int(self.F0.shape[0])

    @property
    def Q1(self) -> np.ndarray:
        """H1 process noise, blockdiag(Q0, Q_a)."""
        n = self.n
        Q1 = np.zeros((n + 1, n + 1))
        Q1[:n, :n] = self.Q0
        Q1[n, n] = self.Q_a
        return Q1

    def H(self, h1: bool = False) -> np.ndarray:
        """The position measurement row, (1, n) or (1, n + 1)."""
        H = np.zeros((1, self.n + int(h1)))
        H[0, 0] = 1.0
        return H


def filter_model(vehicle: Vehicle1D, cfg: LMPConfig) -> FilterModel:
    """The filters' F0, Q0 and Q_a for ``vehicle`` (T, K) and ``cfg`` (A_r, Q0, Q_a, q_model).

    Raises:
        ConfigError: naming ``q_model`` (see :func:`continuous_generator`).
    """
    F0 = transition_h0(vehicle, cfg.A_r)
    n = F0.shape[0]
    q0 = cfg.Q0[:n]  # "known": the reference's entries are unused
    if cfg.q_model == "continuous":
        return FilterModel(F0, discretised_noise(F0, q0, vehicle.T), cfg.Q_a * vehicle.T)
    if n == len(cfg.Q0):
        return FilterModel(F0, np.diag(cfg.Q0), cfg.Q_a)
    return FilterModel(F0, np.diag(q0), cfg.Q_a)


def known_input_removed(
    y: np.ndarray, vehicle: Vehicle1D, cfg: LMPConfig, reference: np.ndarray | None
) -> np.ndarray:
    """y − H m_k, the records (B, N) without the known reference's response (``A_r="known"``; y itself
    otherwise, when ``reference`` must be None).

    ``reference``: [r_k, ṙ_k] at the samples t_k = kT, (N, 2) or per record (B, N, 2); None: the nominal
    reference of ``vehicle`` (its a_r and f_r, :func:`~motionsig_cli.models.vehicle.nominal_reference`),
    the reference of the vehicle the filters assume.
    """
    if cfg.A_r != "known":
        if reference is not None:
            raise ValueError("a known reference applies with A_r='known' only")
        return y
    B, N = y.shape
    ref = nominal_reference(vehicle, np.arange(N) * vehicle.T) if reference is None else reference
    ref = np.asarray(ref, dtype=float)
    if ref.shape not in ((N, 2), (B, N, 2)):
        raise ValueError(f"the known reference must be ({N}, 2) or ({B}, {N}, 2): [r, rdot] per sample")
    return y - reference_response(vehicle, ref)


MAX_CARRIERS = 10_000


def carrier_offsets(lo: float, hi: float, n: float) -> tuple[float, ...]:
    """``n`` carrier offsets f_d [Hz] evenly spaced from ``lo`` to ``hi`` (one: ``lo``), the grid that
    searches an unknown offset of eq (3) around the known f_c (``fc_grid`` = f_c + each).

    Raises:
        ValueError: lo or hi not finite, hi < lo, or n not an integer in 1 … :data:`MAX_CARRIERS`.
    """
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi < lo:
        raise ValueError(f"needs finite lo <= hi; got {lo:g}:{hi:g}")
    if n != int(n) or not 1 <= n <= MAX_CARRIERS:
        raise ValueError(f"needs a number of points n in 1..{MAX_CARRIERS}; got {n:g}")
    return tuple(float(v) for v in np.linspace(lo, hi, int(n)))


@dataclass(frozen=True)
class Candidates:
    """The search grid: 0-based mode index, code phase (samples) and carrier (Hz) per candidate."""

    mode: np.ndarray
    tau: np.ndarray
    f_c: np.ndarray

    def __len__(self) -> int:
        return int(self.mode.size)


def candidate_grid(n_modes: int, n_rho: int, m_rho: int, cfg: LMPConfig) -> Candidates:
    """All (i, τ, f_c) of the configured grid, mode-major."""
    step = m_rho if cfg.tau_grid == "chips" else 1
    taus = np.arange(0, n_rho * m_rho, step)
    i, t, f = np.meshgrid(np.arange(n_modes), taus, np.asarray(cfg.fc_grid, float), indexing="ij")
    return Candidates(i.ravel(), t.ravel(), f.ravel())


@dataclass(frozen=True)
class LMPResult:
    """Statistic per candidate, record and horizon.

    Attributes:
        candidates: The grid.
        horizons: Horizon lengths in samples, (H,).
        J0: H0 cost, (B, H).
        J_cos, J_sin: H1 costs, (C, B, H).
        Lambda: eq (52) statistic, (C, B, H).
        repairs: Sigma-point banks only: (state, innovation) covariance repairs (see
            :mod:`motionsig_cli.filters.unscented`); (0, 0) for Kalman banks.

    Examples:
        See :func:`lmp_detect` for how one is made:

        >>> import numpy as np
        >>> from motionsig_cli import LMPConfig, LMPResult, Vehicle1D, lmp_detect, parse_codes
        >>> codes = parse_codes("corrected")
        >>> y = np.zeros(200)
        >>> res = lmp_detect(y, codes.chips, Vehicle1D(), 2, LMPConfig(), [100, 200])
        >>> isinstance(res, LMPResult), res.Lambda.shape[1:], res.horizons.tolist()
        (True, (1, 2), [100, 200])
    """

    candidates: Candidates
    horizons: np.ndarray
    J0: np.ndarray
    J_cos: np.ndarray
    J_sin: np.ndarray
    Lambda: np.ndarray
    repairs: tuple[int, int] = (0, 0)

    def best(self) -> tuple[np.ndarray, np.ndarray]:
        """argmax index and max value over candidates, each (B, H)."""
        return np.argmax(self.Lambda, axis=0), np.max(self.Lambda, axis=0)

    def runner_up_margin(self) -> np.ndarray:
        """Λ(best) − Λ(second best), (B, H)."""
        top2 = np.sort(self.Lambda, axis=0)[-2:]
        return top2[1] - top2[0]


def progress_steps(n_samples: int, cfg: LMPConfig | RadarLMPConfig, filter: str = "kf") -> int:
    """The time steps :func:`lmp_detect` (``filter`` ``"kf"`` or ``"ukf"``) or :func:`lmp_detect_radar`
    (a :class:`RadarLMPConfig`) report to ``progress`` on records of ``n_samples``: the passes of the H1 bank
    over the record (a Kalman bank: its Riccati recursion and its innovations, plus the white-noise
    expectation with ``center="h0-noise"``; a sigma-point bank: one pass)."""
    if isinstance(cfg, RadarLMPConfig) or filter == "ukf":
        return n_samples
    return n_samples * (3 if cfg.center == "h0-noise" else 2)


def radar_records(y: np.ndarray) -> np.ndarray:
    """Records [range, bearing] as a float array (B, N, 2); one record (N, 2) becomes (1, N, 2)."""
    y = np.asarray(y, dtype=float)
    if y.ndim == 2:
        y = y[None]
    if y.ndim != 3 or y.shape[2] != 2:
        raise ValueError("radar records must be (B, N, 2): range and bearing")
    return y


def checked_horizons(y: np.ndarray, horizons: Sequence[int]) -> np.ndarray:
    """The horizons (samples) as an int array, checked against records y (B, N, …): measurements
    finite or NaN (a missing sample; ±inf is refused), every horizon in 1..N."""
    if np.isinf(y).any():
        raise ValueError("measurements contain inf")
    N = y.shape[1]
    hz = np.asarray(horizons, dtype=int)
    if hz.size == 0 or hz.min() < 1 or hz.max() > N:
        raise ValueError(f"horizons must lie in 1..{N} samples (the record length)")
    return hz


def lmp_detect(
    y: np.ndarray,
    chips: np.ndarray,
    vehicle: Vehicle1D,
    m_rho: int,
    cfg: LMPConfig,
    horizons: Sequence[int],
    *,
    filter: Literal["kf", "ukf"] = "kf",
    sigma: SigmaPointParams | None = None,
    progress: Progress = None,
    block: int | None = None,
    reference: np.ndarray | None = None,
) -> LMPResult:
    """Evaluate eq (52) for every candidate on B measurement records at once.

    Args:
        y: Position measurements, (B, N) (or (N,)); NaN marks a missing sample (predict-only).
        chips: Bipolar codes of the modes, (M, n_ρ).
        vehicle: The model (T, K, R) the filters assume; R_KF = c_r · vehicle.R; with ``A_r="known"`` also
            its nominal reference (a_r, f_r) unless ``reference`` is given.
        m_rho: Samples per chip.
        cfg: Detector settings.
        horizons: Horizons in samples.
        filter: ``"kf"`` (Riccati shared by all records with the same missing samples) or ``"ukf"`` (the
            sigma-point bank on the same linear model: it must reproduce the KF numbers, the cross-check of
            the two banks).
        sigma: Sigma-point parameters for ``"ukf"``.
        progress: Called with the time steps done by the H1 bank, per block of steps; they add up to
            :func:`progress_steps` (the H0 filter, one of 2C + 1, is not counted).
        block: ``"kf"``: evaluate the innovations in consecutive blocks of this many records (see
            :func:`~motionsig_cli.filters.kalman.innovation_costs`); None: all at once.
        reference: ``A_r="known"`` only: the known nominal reference [r_k, ṙ_k], (N, 2) or per record
            (B, N, 2) (:func:`known_input_removed`); None: the vehicle's.

    Examples:
        The statistic of every candidate (mode, code phase) on one 1-D record of the vehicle at rest:

        >>> import numpy as np
        >>> from motionsig_cli import LMPConfig, Vehicle1D, lmp_detect, parse_codes
        >>> chips = parse_codes("corrected").chips  # Table I, 3 modes x 31 chips
        >>> res = lmp_detect(np.zeros(200), chips, Vehicle1D(), 2, LMPConfig(), horizons=[200])
        >>> res.Lambda.shape  # (candidates: 3 modes x 31 code phases, records, horizons)
        (93, 1, 1)
    """
    if filter == "ukf":
        return _lmp_detect_ukf_1d(
            y, chips, vehicle, m_rho, cfg, horizons, sigma or SigmaPointParams(), progress, reference
        )
    y = np.atleast_2d(np.asarray(y, dtype=float))
    hz = checked_horizons(y, horizons)
    groups = missing_patterns(missing_steps(y))
    B, N = y.shape
    y = known_input_removed(y, vehicle, cfg, reference)
    rep = _kf_replicas(chips, vehicle, m_rho, cfg, N)
    cands, z_cos, z_sin = rep.cands, rep.z_cos, rep.z_sin
    C = len(cands)
    R_kf = np.array([[cfg.c_r * vehicle.R]])
    tell = shared_progress(progress, len(groups))

    def bank(skip: np.ndarray | None, yg: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """J0 (b, H), J_cos and J_sin (C, b, H) of records yg (b, N) that miss the samples ``skip``."""
        g = _kf_gains(rep, vehicle, cfg, N, hz, skip, tell)
        J0 = innovation_costs(
            g.F0_at, g.H0, g.g0, np.zeros(g.n), yg, hz, include_logdet=cfg.include_logdet, block=block
        )[0]
        J1 = innovation_costs(
            g.F1_at, g.H1, g.g1, np.zeros(g.n + 1), yg, hz, include_logdet=cfg.include_logdet, progress=tell,
            block=block,
        )  # fmt: skip
        J_cos, J_sin = J1[:C], J1[C:]
        if g.E0 is not None and g.E1 is not None:  # centre every J on its expectation under white noise of R
            J0 = J0 - g.E0[None, :]
            J_cos, J_sin = J_cos - g.E1[:C, None, :], J_sin - g.E1[C:, None, :]
        return J0, J_cos, J_sin

    def statistic(
        skip: np.ndarray | None, J0: np.ndarray, J_cos: np.ndarray, J_sin: np.ndarray
    ) -> np.ndarray:
        if cfg.weights == "paper":
            return 2 * J0[None] - J_cos - J_sin  # eq (52)
        zc2, zs2 = z_cos**2, z_sin**2
        if skip is not None:  # c sums over the samples that are present
            zc2, zs2 = zc2 * ~skip, zs2 * ~skip
        csum_cos = np.cumsum(zc2, axis=1)[:, hz - 1] / R_kf[0, 0]  # c_cos over each horizon, eq (36)
        csum_sin = np.cumsum(zs2, axis=1)[:, hz - 1] / R_kf[0, 0]
        return csum_cos[:, None, :] * (J0[None] - J_cos) + csum_sin[:, None, :] * (
            J0[None] - J_sin
        )  # eqs (38), (40)

    if len(groups) == 1:
        skip = groups[0][0]
        J0, J_cos, J_sin = bank(skip, y)
        return LMPResult(cands, hz, J0, J_cos, J_sin, statistic(skip, J0, J_cos, J_sin))
    J0 = np.empty((B, hz.size))
    J_cos, J_sin, Lam = (np.empty((C, B, hz.size)) for _ in range(3))
    for skip, idx in groups:  # one Riccati recursion per missing pattern (not per record or filter)
        j0, jc, js = bank(skip, y[idx])
        J0[idx], J_cos[:, idx], J_sin[:, idx] = j0, jc, js
        Lam[:, idx] = statistic(skip, j0, jc, js)
    return LMPResult(cands, hz, J0, J_cos, J_sin, Lam)


def _lmp_detect_ukf_1d(
    y: np.ndarray, chips: np.ndarray, vehicle: Vehicle1D, m_rho: int, cfg: LMPConfig, horizons: Sequence[int],
    sigma: SigmaPointParams, progress: Progress = None, reference: np.ndarray | None = None,
) -> LMPResult:  # fmt: skip
    """The 1-D bank of :func:`lmp_detect` run by the sigma-point filters (exact for this linear model)."""
    if cfg.center != "none" or cfg.weights != "paper":
        raise ValueError("the sigma-point bank supports center='none' and weights='paper' only")
    y = np.atleast_2d(np.asarray(y, dtype=float))
    N = y.shape[1]
    hz = np.asarray(horizons, dtype=int)
    y = known_input_removed(y, vehicle, cfg, reference)
    cands = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg)
    R_kf = np.array([[cfg.c_r * vehicle.R]])
    model = filter_model(vehicle, cfg)
    n, F0 = model.n, model.F0
    c0 = ukf_bank_costs(
        StructuredTransition.constant(F0, N),
        model.Q0,
        linear_measurement(model.H(), R_kf),
        np.zeros(n),
        cfg.P0 * np.eye(n),
        y,
        hz,
        sigma,
    )
    z_cos, z_sin, zd_cos, zd_sin = replica_bank(
        chips, cands.mode, cands.tau, cands.f_c, vehicle.T, m_rho, N, cfg.zdot
    )
    gcol = np.concatenate(
        [amplitude_column(vehicle, z_cos, zd_cos), amplitude_column(vehicle, z_sin, zd_sin)]
    )
    F1 = np.zeros((n + 1, n + 1))
    F1[:n, :n] = F0
    F1[n, n] = 1.0
    c1 = ukf_bank_costs(
        StructuredTransition(F1, ((1, n),), gcol[:, :, None]),
        model.Q1,
        linear_measurement(model.H(h1=True), R_kf),
        np.zeros(n + 1),
        cfg.P0 * np.eye(n + 1),
        y,
        hz,
        sigma,
        progress=progress,
    )
    return _assemble(cands, hz, c0, c1, cfg.include_logdet)


def _assemble(cands: Candidates, hz: np.ndarray, c0: BankCosts, c1: BankCosts, logdet: bool) -> LMPResult:
    """Λ = 2 J_H0 − J_cos − J_sin (eq 52) from the costs of a sigma-point H0 filter and 2C H1 filters."""
    C = len(cands)
    J0 = c0.J[0] + (c0.half_logdet[0] if logdet else 0.0)
    J1 = c1.J + (c1.half_logdet if logdet else 0.0)
    J_cos, J_sin = J1[:C], J1[C:]
    reps = (c0.repairs_P + c1.repairs_P, c0.repairs_S + c1.repairs_S)
    return LMPResult(cands, hz, J0, J_cos, J_sin, 2 * J0[None] - J_cos - J_sin, reps)


@dataclass(frozen=True, slots=True)
class RadarLMPConfig:
    """Detector settings for the 2-D radar example.

    Attributes:
        c_r: Filter measurement covariance R_UKF = c_r · diag(R_κ, R_χ), finite and > 0 (assumed: the
            paper's "best trade-off" c_r = 100 of the 1-D example; it states none for the radar, and
            c_r = 1 follows Fig 7's shape more closely).
        Q0: Per-step process noise of the 8 H0 states (eq 61), finite and >= 0.
        Q1: Per-step process noise of the 10 H1 states (eq 62), finite and >= 0.
        P0: Prior covariance scale, identity × P0 (assumed: P0 = 1; the paper does not state it).
        tau_grid, fc_grid, include_logdet, zdot: As in :class:`LMPConfig`.
        sigma: Scaled unscented-transform parameters (α, β, κ) (assumed: 1, 2, 0; the paper does not
            state them); they must suit both the 8-state and the 10-state filters.

    Examples:
        >>> from motionsig_cli import RadarLMPConfig
        >>> len(RadarLMPConfig().Q0), len(RadarLMPConfig().Q1)  # the 8- and 10-state models, eqs (61)-(62)
        (8, 10)
    """

    c_r: float = 100.0
    Q0: tuple[float, ...] = Q0_2D
    Q1: tuple[float, ...] = Q1_2D
    P0: float = 1.0
    tau_grid: Literal["chips", "samples"] = "chips"
    fc_grid: tuple[float, ...] = (1.0,)
    include_logdet: bool = False
    zdot: Literal["analytic", "finite-difference"] = "analytic"
    sigma: SigmaPointParams = field(default_factory=SigmaPointParams)

    def __post_init__(self) -> None:
        positive("c_r", self.c_r)
        check_variances(
            "Q0", self.Q0, 8, "the H0 states [x, xdot, y, ydot, r_x, rdot_x, r_y, rdot_y] (eq 61)"
        )
        check_variances("Q1", self.Q1, 10, "the H1 states [..., a_x, a_y] (eq 62)")
        positive("P0", self.P0)
        check_grid(self.tau_grid, self.fc_grid, self.include_logdet, self.zdot)
        if not isinstance(self.sigma, SigmaPointParams):
            raise ConfigError("sigma", self.sigma, "is not a SigmaPointParams")
        self.sigma.weights(8)  # n + λ = α²(n + κ) > 0 and a usable centre weight, H0 and H1 filters
        self.sigma.weights(10)

    @property
    def as_grid(self) -> LMPConfig:
        """The 1-D config carrying this one's search grid (for :func:`candidate_grid`)."""
        return LMPConfig(tau_grid=self.tau_grid, fc_grid=self.fc_grid)


def _range_bearing_rows(s: np.ndarray) -> np.ndarray:
    """Eq (60) for states stacked on the first axis (x = s[0], y = s[2]); the bank's hot path. The range is
    √(x² + y²) (not np.hypot, whose overflow guard costs more than the rest of the range: positions are far
    from 1e154 m), written with the bearing straight into one array."""
    x, y = np.asarray(s[0], dtype=float), np.asarray(s[2], dtype=float)
    out = np.empty((2, *x.shape))
    r = np.multiply(x, x, out=out[0, ...])
    r += y * y
    np.sqrt(r, out=r)
    np.arctan2(y, x, out=out[1, ...])
    return out


def radar_measurement(vehicle: Vehicle2D, c_r: float) -> SigmaMeasurement:
    """Eq (60) for the bank: h reads (x, ẋ, y) (lead 3), bearing angular, R = c_r diag(R_κ, R_χ)."""
    return SigmaMeasurement(
        _range_bearing_rows,
        3,
        c_r * np.diag([vehicle.R_range, vehicle.R_bearing]),
        (False, True),
    )


def lmp_detect_radar(
    y: np.ndarray,
    chips: np.ndarray,
    vehicle: Vehicle2D,
    m_rho: int,
    cfg: RadarLMPConfig,
    horizons: Sequence[int],
    *,
    progress: Progress = None,
) -> LMPResult:
    """Eq (52) with sigma-point filters on range/bearing records (the paper's §IV.B, eqs 59–62).

    H0: one filter on the 8-state model of eq (61). H1: for every candidate one filter with the
    replica z_cos and one with z_sin on the 10-state model of eq (62), the amplitudes a_x and a_y
    entering the ẋ and ẏ rows with T (k1 z_k + k2 ż_k) (the same replica on both axes).

    Args:
        y: Records [range, bearing] (B, N, 2) (or (N, 2)), bearing in radians.
        chips: Bipolar codes (M, n_ρ).  vehicle: T, K, start, R_κ, R_χ the filters assume.
        m_rho: Samples per chip.  cfg: Detector settings.  horizons: Horizons in samples.
        progress: Called with the time steps done by the H1 bank (2C of the 2C + 1 filters), per block of
            steps; they add up to the record length.

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli import RadarLMPConfig, Vehicle2D, lmp_detect_radar, parse_codes
        >>> chips = parse_codes("corrected").chips
        >>> v = Vehicle2D()
        >>> y = np.tile([np.hypot(*v.start), np.arctan2(v.start[1], v.start[0])], (40, 1))  # range, bearing
        >>> res = lmp_detect_radar(y, chips, v, 2, RadarLMPConfig(), horizons=[40])
        >>> res.Lambda.shape
        (93, 1, 1)
    """
    y = radar_records(y)
    hz = checked_horizons(y, horizons)
    N = y.shape[1]
    cands = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid)
    meas = radar_measurement(vehicle, cfg.c_r)

    z_cos, z_sin, zd_cos, zd_sin = replica_bank(
        chips, cands.mode, cands.tau, cands.f_c, vehicle.T, m_rho, N, cfg.zdot
    )
    k1, k2 = vehicle.K
    g = vehicle.T * (k1 * np.concatenate([z_cos, z_sin]) + k2 * np.concatenate([zd_cos, zd_sin]))  # (2C, N)
    F1 = transition_h1_2d_base(vehicle.T, vehicle.K)
    x0 = prior_mean_2d(vehicle.start, True)
    # One bank: the H0 filter (8 states of eq 61) as filter 0, its amplitudes padding (F1 restricted to
    # the first 8 states is F^H0, no entry for it, Q and P0 zero on the padding), then the 2C H1 filters
    if not (np.array_equal(F1[:8, :8], transition_h0_2d(vehicle.T, vehicle.K))
            and np.array_equal(x0[:8], prior_mean_2d(vehicle.start, False))):  # fmt: skip
        raise AssertionError("the H1 model no longer extends the H0 model")
    gh = np.concatenate([np.zeros((1, N)), g])
    Q = np.stack([np.diag([*cfg.Q0, 0.0, 0.0])] + [np.diag(cfg.Q1)] * g.shape[0])
    costs = ukf_bank_costs(
        StructuredTransition(F1, AMPLITUDE_ENTRIES_2D, np.repeat(gh[:, :, None], 2, axis=2)),
        Q, meas, x0, cfg.P0 * np.eye(10), y, hz, cfg.sigma, progress=progress,
        states=[8] + [10] * g.shape[0],
    )  # fmt: skip
    c0 = BankCosts(costs.J[:1], costs.half_logdet[:1], costs.repairs_P, costs.repairs_S)
    c1 = BankCosts(costs.J[1:], costs.half_logdet[1:], 0, 0)
    return _assemble(cands, hz, c0, c1, cfg.include_logdet)


# ------------------------------------------------------------------- the Kalman bank's fixed part, cached
_REPLICAS: BytesLRU[_KfReplicas] = BytesLRU()
_GAINS: BytesLRU[_KfGains] = BytesLRU()


@dataclass(frozen=True, eq=False)
class _KfReplicas:
    """The candidates of :func:`lmp_detect` and their replicas z_cos, z_sin (C, N) and amplitude columns
    gcol (2C, N): the cos block, then the sin block (eq 44)."""

    key: str
    cands: Candidates
    z_cos: np.ndarray
    z_sin: np.ndarray
    gcol: np.ndarray


def _kf_replicas(chips: np.ndarray, vehicle: Vehicle1D, m_rho: int, cfg: LMPConfig, N: int) -> _KfReplicas:
    """The replicas of every candidate, kept per process (:mod:`motionsig_cli.cache`)."""
    key = cache.key_of("lmp-replicas", chips, vehicle.T, vehicle.K, m_rho, cfg, N)  # what the replicas read

    def build() -> tuple[_KfReplicas, int]:
        cands = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg)
        z_cos, z_sin, zd_cos, zd_sin = replica_bank(
            chips, cands.mode, cands.tau, cands.f_c, vehicle.T, m_rho, N, cfg.zdot
        )
        gcol = np.concatenate(
            [amplitude_column(vehicle, z_cos, zd_cos), amplitude_column(vehicle, z_sin, zd_sin)]
        )  # (2C, N): T (k1 z_k + k2 ż_k), eq (44)
        return _KfReplicas(key, cands, z_cos, z_sin, gcol), cache.freeze((z_cos, z_sin, gcol))

    return _REPLICAS.get(key, build)[0]


@dataclass(frozen=True, eq=False)
class _KfGains:
    """The measurement-independent part of the two banks for one pattern of missing samples: transitions,
    gains and (``center="h0-noise"``) the expected costs E0 (H,) and E1 (2C, H) under white noise."""

    n: int
    H0: np.ndarray
    H1: np.ndarray
    F0_at: Callable[[int], np.ndarray]
    F1_at: Callable[[int], np.ndarray]
    g0: BankGains
    g1: BankGains
    E0: np.ndarray | None
    E1: np.ndarray | None


def _kf_gains(
    rep: _KfReplicas,
    vehicle: Vehicle1D,
    cfg: LMPConfig,
    N: int,
    hz: np.ndarray,
    skip: np.ndarray | None,
    tell: Progress,
) -> _KfGains:
    """The H0 filter's and the 2C H1 filters' Riccati recursions (and expected costs), kept per process: a
    hit reports to ``tell`` the steps the recursions would have reported, so progress adds up either way."""
    centre = cfg.center == "h0-noise"
    key = cache.key_of("lmp-gains", rep.key, vehicle, cfg, N, hz, np.zeros(0) if skip is None else skip)

    def build() -> tuple[_KfGains, int]:
        model = filter_model(vehicle, cfg)
        n, F0, Q0, Q1 = model.n, model.F0, model.Q0, model.Q1  # H0: n states (4, or 2 with a known reference)
        H0m, H1m = model.H(), model.H(h1=True)
        R_kf = np.array([[cfg.c_r * vehicle.R]])
        gcol = rep.gcol
        F1 = np.zeros((gcol.shape[0], n + 1, n + 1))  # H1: n + 1 states, time-varying a-column (eq 44)
        F1[:, :n, :n] = F0
        F1[:, n, n] = 1.0

        def F0_at(k: int) -> np.ndarray:
            return F0

        def F1_at(k: int) -> np.ndarray:
            F1[:, 1, n] = gcol[:, k]  # T (k1 z_k + k2 ż_k)
            return F1

        g0 = riccati(F0_at, H0m, Q0, R_kf, cfg.P0 * np.eye(n), N, 1, skip=skip)
        g1 = riccati(F1_at, H1m, Q1, R_kf, cfg.P0 * np.eye(n + 1), N, gcol.shape[0], progress=tell, skip=skip)
        E0 = E1 = None
        if centre:
            R_true = np.array([[vehicle.R]])
            E0 = expected_costs_white_noise(F0_at, H0m, g0, R_true, N, hz)[0]
            E1 = expected_costs_white_noise(F1_at, H1m, g1, R_true, N, hz, progress=tell)
        arrays = [g.K for g in (g0, g1)] + [g.S_inv for g in (g0, g1)] + [g.logdet_2pi_S for g in (g0, g1)]
        arrays += [st.values for st in (g0.transition, g1.transition) if st is not None]
        arrays += [e for e in (E0, E1) if e is not None]
        size = cache.freeze(arrays)
        return _KfGains(n, H0m, H1m, F0_at, F1_at, g0, g1, E0, E1), size

    g, hit = _GAINS.get(key, build)
    if hit and tell is not None:  # the steps the H1 recursion (and its expectation) would have reported
        tell(N)
        if centre:
            tell(N)
    return g
