"""One simulated record of the closed-loop vehicle carrying a mode signature (``motionsig simulate``): the
1-D example (eqs 53–55, Fig 2) and the 2-D radar example (eqs 59–60) of the mode-signature paper (47th IEEE CDC, Cancún, 2008).

The random inputs (mode, code phase, carrier phase, noise) are those of Monte Carlo trial 0 of the
detection experiments (:func:`motionsig_cli.modesig.lmp1d.draw_trial`) at the same seed; a mode, code
phase or carrier phase given in the configuration replaces its draw. The record is a table: one row per
sample (time, measurement, true state, references, signature, control) and metadata carrying every
parameter a detector needs to read it back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of, positive
from motionsig_cli.models.vehicle import ONBOARD_ESTIMATOR, Vehicle1D, nominal_reference, simulate_1d
from motionsig_cli.models.vehicle2d import SEED_ANR_PAIRS, Vehicle2D, anr_pair_variances, simulate_2d
from motionsig_cli.modesig.record_reading import MAX_RECORD
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.signals.code_spec import parse_codes
from motionsig_cli.signals.signature import MAX_TAU, SignatureConfig, finite
from motionsig_cli.tables import Table, make_meta

N_MODES = 3  # Table I
CODES = ("corrected", "printed")
ZDOT_METHODS = ("analytic", "finite-difference")

ASSUMPTIONS_1D = (
    "assumed, the mode-signature paper does not state them: T, m_rho, the feedback gain K (by default "
    "pole placement at wn = 4 pi rad/s, zeta = 0.7), sigma_a, the initial state x0 = 0 and a sine "
    "nominal reference"
)
# the metadata's "feedback" (read back by detect) per Vehicle1D.feedback
FEEDBACK_META = {"true": "true state", "estimate": "estimate"}
ASSUMPTIONS_2D = (
    "assumed, the mode-signature paper does not state them: T, m_rho, K (the same on both axes), sigma_a, "
    "the references x0 + a_r sin(2 pi f_r t) and y0 + a_r sin(2 pi f_r t), the signature on the axes of "
    "sig_axes with a_x = a_y = a_sig; R_range is inverted from the printed range ANR label of Fig 7"
)

COLUMNS_1D = ("k", "t", "y", "x", "xdot", "r", "rdot", "z", "zdot", "u")
COLUMNS_ESTIMATE = ("xhat", "xdothat")  # feedback="estimate": the onboard estimate the controller used
COLUMNS_2D = (
    "k", "t", "range", "bearing", "x", "xdot", "y", "ydot",
    "r_x", "rdot_x", "r_y", "rdot_y", "z", "zdot", "u_x", "u_y",
)  # fmt: skip


@dataclass(frozen=True)
class RecordConfig:
    """What to simulate: the vehicle, the signature it carries, the record length and the seed.

    Checked here, once: codes a code set (:func:`~motionsig_cli.signals.code_spec.parse_codes`); mode an
    integer 1 … the number of codes (1–3 for Table I); tau or tau_chips (not both) an integer code phase
    with |tau| ≤ 2^53 samples; theta, f_c, m_rho and T through :class:`SignatureConfig`; duration > 0
    and between one sample and :data:`MAX_RECORD` samples at the vehicle's T; zdot one of its
    choices; signature a bool; seed an integer ≥ 0; anr_pair (2-D only) 1–4 and the pair the vehicle's
    variances came from.

    Attributes:
        vehicle: The 1-D (:class:`Vehicle1D`) or 2-D radar (:class:`Vehicle2D`) vehicle.
        mode: Mode 1 … the number of codes (Table I: 1–3); None: drawn from the seed.
        tau: Code phase [samples]; None (and no tau_chips): drawn on the chip grid.
        tau_chips: Code phase in chips (tau = tau_chips · m_rho).
        theta: Carrier phase [rad]; None: drawn from the seed.
        f_c: Carrier frequency [Hz].
        m_rho: Samples per chip (assumed: 20; the paper does not state it).
        duration: Record length [s]; the record has round(duration / T) samples.
        codes: The mode codes (mode i carries code i): Table I's ``"corrected"`` or ``"printed"``, or any
            code set :func:`~motionsig_cli.signals.code_spec.parse_codes` reads (``"gold:45,75:5"``…).
        signature: False simulates H0 (no signature).
        zdot: Signature derivative in the velocity reference, ``"analytic"`` or ``"finite-difference"``.
        seed: Root seed (the record is trial 0).
        anr_pair: 2-D: the Fig 7 ANR pair both noise variances came from (metadata), or None.

    Raises:
        ConfigError: naming the first bad field.
    """

    vehicle: Vehicle1D | Vehicle2D
    mode: int | None = None
    tau: int | None = None
    tau_chips: int | None = None
    theta: float | None = None
    f_c: float = 1.0
    m_rho: int = 20
    duration: float = 80.0
    codes: str = "corrected"
    signature: bool = True
    zdot: str = "analytic"
    seed: int = DEFAULT_SEED
    anr_pair: int | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.vehicle, Vehicle1D | Vehicle2D):
            raise ConfigError("vehicle", type(self.vehicle).__name__, "is not a Vehicle1D or a Vehicle2D")
        n_modes = parse_codes(self.codes).n_modes
        if self.mode is not None and integer("mode", self.mode) not in range(1, n_modes + 1):
            table1 = self.codes in CODES
            what = "a Table I mode: 1, 2 or 3" if table1 else f"a mode of the {n_modes} codes: 1 to {n_modes}"
            raise ConfigError("mode", self.mode, f"is not {what}")
        if self.tau is not None and self.tau_chips is not None:
            raise ConfigError("tau_chips", self.tau_chips, "is given together with tau: give one, not both")
        if self.theta is not None:
            finite("theta", self.theta)
        SignatureConfig(
            T=self.vehicle.T, m_rho=self.m_rho, f_c=self.f_c, tau=0 if self.tau is None else self.tau
        )
        if isinstance(self.vehicle, Vehicle1D) and self.f_c + self.vehicle.f_d < 0:
            raise ConfigError(
                "f_d", self.vehicle.f_d, f"makes the received carrier f_c + f_d = {self.f_c + self.vehicle.f_d:g} Hz "
                "negative",
            )  # fmt: skip
        if self.tau_chips is not None and abs(integer("tau_chips", self.tau_chips) * self.m_rho) > MAX_TAU:
            raise ConfigError("tau_chips", self.tau_chips, f"is beyond 2^53 samples at m_rho = {self.m_rho}")
        positive("duration", self.duration, unit="s")
        ratio = self.duration / self.vehicle.T
        if not math.isfinite(ratio) or round(ratio) > MAX_RECORD:
            raise ConfigError(
                "duration",
                self.duration,
                f"gives {ratio:.4g} samples at T = {self.vehicle.T:g} s, more than {MAX_RECORD}: shorten it "
                "or lengthen T",
            )
        if round(ratio) < 1:
            raise ConfigError(
                "duration", self.duration, f"is shorter than one sample (T = {self.vehicle.T:g} s)"
            )
        if not isinstance(self.signature, bool):
            raise ConfigError("signature", self.signature, "is not True or False")
        one_of("zdot", self.zdot, ZDOT_METHODS)
        integer("seed", self.seed, 0)
        if self.anr_pair is not None:
            if not isinstance(self.vehicle, Vehicle2D):
                raise ConfigError("anr_pair", self.anr_pair, "applies to the 2-D radar vehicle only")
            variances = anr_pair_variances(self.anr_pair, self.vehicle.a_sig)
            if variances != (self.vehicle.R_range, self.vehicle.R_bearing):
                raise ConfigError(
                    "anr_pair", self.anr_pair, "is not the pair of the vehicle's noise variances"
                )

    @property
    def two_d(self) -> bool:
        """Whether this is the 2-D radar example."""
        return isinstance(self.vehicle, Vehicle2D)

    @property
    def n_samples(self) -> int:
        """Samples in the record: round(duration / T)."""
        return round(self.duration / self.vehicle.T)


@dataclass(frozen=True)
class SimulatedRecord:
    """A simulated record: the table (rows and metadata) and the arrays of its figure.

    Attributes:
        table: One row per sample; ``table.meta`` is the provenance (every parameter).
        t: Times (N,).
        x: True state, (N, 2) [x, ẋ] (1-D) or (N, 4) [x, ẋ, y, ẏ] (2-D).
        r: Nominal references, (N, 2) (1-D) or (N, 4) [r_x, ṙ_x, r_y, ṙ_y] (2-D).
        y: Measurements, (N,) position (1-D) or (N, 2) [range, bearing] (2-D).
        z: The signature as applied (zero without one), (N,).
        a_sig: Signature amplitude.
        summary: One line for people.
    """

    table: Table
    t: np.ndarray
    x: np.ndarray
    r: np.ndarray
    y: np.ndarray
    z: np.ndarray
    a_sig: float
    summary: str

    @property
    def two_d(self) -> bool:
        """Whether this is a 2-D radar record."""
        return self.x.shape[1] == 4

    @property
    def combined_reference(self) -> np.ndarray:
        """1-D: the position reference r + a_sig z the loop follows (Fig 2)."""
        return self.r[:, 0] + self.a_sig * self.z


def simulate_record(cfg: RecordConfig) -> SimulatedRecord:
    """Simulate one record: draw trial 0's inputs, sample the signature (eqs 1–3), run the closed loop
    (eqs 53–55, or 59–60 for the radar), and tabulate it.

    Raises:
        ConfigError: the loop diverges (non-finite state: K, or the largest input), or, 2-D, the vehicle
            passes within 10 range-noise standard deviations of the radar (start or R_range) or a measured
            range is ≤ 0 (R_range).
    """
    from motionsig_cli.modesig.lmp1d import draw_trial, own_sensor_noise, signature_batch

    vehicle, n, m_rho = cfg.vehicle, cfg.n_samples, cfg.m_rho
    codes = parse_codes(cfg.codes)
    chips = codes.chips
    draw = draw_trial(cfg.seed, 0, n, chips.shape[0], chips.shape[1], m_rho, dims=2 if cfg.two_d else 1)
    mode0 = draw.mode if cfg.mode is None else cfg.mode - 1
    tau0 = (
        cfg.tau if cfg.tau is not None else cfg.tau_chips * m_rho if cfg.tau_chips is not None else draw.tau
    )
    th = draw.theta if cfg.theta is None else cfg.theta
    f_d = vehicle.f_d if isinstance(vehicle, Vehicle1D) else 0.0
    z, zd = signature_batch(
        chips,
        np.array([mode0]),
        np.array([tau0]),
        np.array([th]),
        cfg.f_c + f_d,
        vehicle.T,
        m_rho,
        n,
        cfg.zdot,
    )  # the received carrier f_c + f_d, eq (3)
    if not cfg.signature:
        z, zd = np.zeros_like(z), np.zeros_like(zd)
    common = dict(
        mode=mode0 + 1, tau=int(tau0), tau_chips=tau0 / m_rho, theta=th, signature=cfg.signature,
        a_sig=vehicle.a_sig, a_r=vehicle.a_r, f_r=vehicle.f_r, f_c=cfg.f_c, f_d=f_d, T=vehicle.T, m_rho=m_rho,
        n_rho=int(chips.shape[1]), K=list(vehicle.K), sigma_a=vehicle.sigma_a,
    )  # fmt: skip
    estimate = isinstance(vehicle, Vehicle1D) and vehicle.feedback == "estimate"
    tail = dict(
        duration=n * vehicle.T,
        n_samples=n,
        codes=codes.spec,
        feedback=FEEDBACK_META[vehicle.feedback] if isinstance(vehicle, Vehicle1D) else "true state",
        **({"onboard_estimator": ONBOARD_ESTIMATOR} if estimate else {}),
        zdot=cfg.zdot,
        seed=cfg.seed,
        trial=0,
        **({"own_sensor_stream": "SeedSequence(seed, spawn_key=(0, 3))"} if estimate else {}),
    )
    head = f"mode {mode0 + 1}, tau {tau0} samples, theta {th:.3f} rad"
    v_own = own_sensor_noise(vehicle, cfg.seed, [0], n) if isinstance(vehicle, Vehicle1D) else None
    drawn = _Drawn(z[0], zd[0], draw.w, draw.v, common, tail, head, None if v_own is None else v_own[0])
    if isinstance(vehicle, Vehicle2D):
        return _record_2d(cfg, vehicle, drawn)
    return _record_1d(vehicle, drawn)


@dataclass(frozen=True, eq=False)
class _Drawn:
    """Trial 0's signature z, ż and noises w, v, and what the 1-D and 2-D tables share: the metadata
    before (``common``) and after (``tail``) the example's own keys, and the summary's ``head``."""

    z: np.ndarray
    zd: np.ndarray
    w: np.ndarray
    v: np.ndarray
    common: dict[str, Any]
    tail: dict[str, Any]
    head: str
    v_own: np.ndarray | None = None  # feedback="estimate": the vehicle's own sensor noise (N,)


def _record_1d(vehicle: Vehicle1D, drawn: _Drawn) -> SimulatedRecord:
    """The 1-D closed loop (eqs 53–55) and its table."""
    z, zd, common, tail, head = drawn.z, drawn.zd, drawn.common, drawn.tail, drawn.head
    v_own = None if drawn.v_own is None else drawn.v_own[None, :]
    with np.errstate(over="ignore", invalid="ignore"):  # a divergent loop is reported below
        sim = simulate_1d(vehicle, z[None], zd[None], drawn.w[None, :], drawn.v[None, :], v_own)
    x, y, u, t = sim["x"][0], sim["y"][0], sim["u"][0], sim["t"]
    _check_finite(vehicle, x, y)
    anr = vehicle.anr
    anr_log10 = 10 * math.log10(anr) if anr > 0 else None
    anr_ln = 10 * math.log(anr) if anr > 0 else None
    meta = make_meta(
        "simulate",
        example="1d",
        **common,
        R=vehicle.R,
        anr_linear=anr,
        anr_db_log10=anr_log10,
        anr_db_paper_ln=anr_ln,
        **tail,
        assumptions=ASSUMPTIONS_1D,
    )
    r = nominal_reference(vehicle, t)
    rows = [
        (
            k,
            float(t[k]),
            float(y[k]),
            float(x[k, 0]),
            float(x[k, 1]),
            float(r[k, 0]),
            float(r[k, 1]),
            float(z[k]),
            float(zd[k]),
            float(u[k]),
        )
        for k in range(t.size)
    ]
    columns = COLUMNS_1D
    if "xhat" in sim:  # the onboard estimate the controller used (feedback="estimate")
        xh = sim["xhat"][0]
        rows = [(*row, float(xh[k, 0]), float(xh[k, 1])) for k, row in enumerate(rows)]
        columns = COLUMNS_1D + COLUMNS_ESTIMATE
    if vehicle.f_d:
        head += f", carrier f_c + f_d = {drawn.common['f_c'] + vehicle.f_d:g} Hz"
    if vehicle.feedback == "estimate":
        head += ", feedback on the onboard estimate"
    summary = f"simulated {t.size} samples: {head}, R {vehicle.R:g}" + (
        f" (ANR {anr:.4g} = {anr_log10:.1f} dB; the paper's 10*ln label {anr_ln:.1f})"
        if anr > 0
        else " (ANR 0)"
    )
    return SimulatedRecord(Table(columns, rows, meta), t, x, r, y, z, vehicle.a_sig, summary)


def _record_2d(cfg: RecordConfig, vehicle: Vehicle2D, drawn: _Drawn) -> SimulatedRecord:
    """The 2-D radar example (eqs 59–60): trajectory and range/bearing record."""
    z, zd, common, tail, head = drawn.z, drawn.zd, drawn.common, drawn.tail, drawn.head
    with np.errstate(over="ignore", invalid="ignore"):  # a divergent loop is reported below
        sim = simulate_2d(vehicle, z[None], zd[None], drawn.w[None], drawn.v[None])
    x, y, u, r, t = sim["x"][0], sim["y"][0], sim["u"][0], sim["r"], sim["t"]
    _check_finite(vehicle, x, y)
    _check_radar_geometry(vehicle, x, y)
    anr_angle, anr_range = vehicle.anr
    pair = cfg.anr_pair
    meta = make_meta(
        "simulate",
        example="2d",
        **common,
        R_range=vehicle.R_range,
        R_bearing=vehicle.R_bearing,
        anr_pair=pair,
        seed_anr_pair_labels=None if pair is None else list(SEED_ANR_PAIRS[pair - 1]),
        anr_angle_linear=anr_angle,
        anr_angle_db_paper_ln=10 * math.log(anr_angle) if anr_angle > 0 else None,
        anr_angle_db_log10=10 * math.log10(anr_angle) if anr_angle > 0 else None,
        anr_range_linear=anr_range,
        anr_range_db_paper_ln=10 * math.log(anr_range) if anr_range > 0 else None,
        anr_range_db_log10=10 * math.log10(anr_range) if anr_range > 0 else None,
        start=list(vehicle.start),
        sig_axes=vehicle.sig_axes,
        bearing_unit="rad",
        radar="origin",
        **tail,
        assumptions=ASSUMPTIONS_2D,
    )
    rows = [
        (k, float(t[k]), *(float(c) for c in (*y[k], *x[k], *r[k], z[k], zd[k], *u[k])))
        for k in range(t.size)
    ]
    summary = (
        f"simulated {t.size} samples (2-D radar): {head}, R_range {vehicle.R_range:.3g} m^2, "
        f"R_bearing {vehicle.R_bearing:.3g} rad^2"
        + (
            f" (the paper's 10*ln ANR: angle {10 * math.log(anr_angle):.1f}, "
            f"range {10 * math.log(anr_range):.1f})"
            if anr_angle > 0
            else ""
        )
    )
    return SimulatedRecord(Table(COLUMNS_2D, rows, meta), t, x, r, y, z, vehicle.a_sig, summary)


def _check_finite(vehicle: Vehicle1D | Vehicle2D, x: np.ndarray, y: np.ndarray) -> None:
    """A loop that overflowed: blame K when A − BK is unstable, else the largest of the inputs."""
    if np.all(np.isfinite(x)) and np.all(np.isfinite(y)):
        return
    T, (k1, k2) = vehicle.T, vehicle.K
    if max(abs(np.linalg.eigvals(np.array([[1.0, T], [-T * k1, 1.0 - T * k2]])))) >= 1.0:
        raise ConfigError(
            "K",
            tuple(vehicle.K),
            "makes the closed loop unstable: the simulated state overflows within the record",
        )
    sizes = {"a_r": vehicle.a_r, "a_sig": vehicle.a_sig, "sigma_a": vehicle.sigma_a}
    if isinstance(vehicle, Vehicle2D):
        sizes["start"] = max(abs(s) for s in vehicle.start)
    name = max(sizes, key=lambda k: sizes[k])
    raise ConfigError(
        name,
        getattr(vehicle, name),
        "is too large: the simulated state overflows (non-finite) within the record",
    )


def _check_radar_geometry(vehicle: Vehicle2D, x: np.ndarray, y: np.ndarray) -> None:
    """The bearing is undefined at the radar: refuse a path within 10 range-noise standard deviations of
    it (blaming the start when the path closes in on the radar, to less than half its initial range, and
    the range noise otherwise), and a measured range ≤ 0."""
    near = 10 * math.sqrt(vehicle.R_range)
    true_range = np.hypot(x[:, 0], x[:, 2])
    closest = float(true_range.min())
    if closest <= near:
        k = int(np.argmin(true_range))
        where = (
            f"the vehicle passes within {closest:.3g} m of the radar at t = {k * vehicle.T:g} s "
            f"(10 range-noise standard deviations: {near:.3g} m), where the bearing is undefined"
        )
        if closest < 0.5 * true_range[0]:
            raise ConfigError("start", vehicle.start, f"is too close to the radar: {where}; move the start")
        raise ConfigError("R_range", vehicle.R_range, f"is too large: {where}; lower it")
    if np.any(y[:, 0] <= 0):
        k = int(np.flatnonzero(y[:, 0] <= 0)[0])
        raise ConfigError(
            "R_range",
            vehicle.R_range,
            f"makes a measured range <= 0 (t = {k * vehicle.T:g} s): the range noise exceeds the range; "
            "lower it",
        )
