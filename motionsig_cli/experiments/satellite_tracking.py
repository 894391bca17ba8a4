"""ATC-10 §4 experiments: the two example constellations (Table 4.1), the constellation constants
(Table 4.2), the estimation parameters (Table 4.3), the RMS-error curves (Figs 4.2/4.3) and a Monte Carlo
of the estimators on nonlinear time-of-arrival measurements.

Conventions (project decision, see the errata page):

- ``corrected`` (default): exact speed of light, the geosynchronous orbit radius, and the
  frame-independent three-satellite constant b3 = 1'(UU')⁻¹1 (eq 4.5.30 corrected);
- ``report``: c = 1 ft/ns, r_sat = 9.235 Earth radii, and the printed b3 (the frame-dependent
  1'(U'U)⁻¹1) — this reproduces Tables 4.2 and 4.3.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from motionsig_cli.engine import Engine, run_tasks, tasks_of, trials_per_task
from motionsig_cli.refdata import load
from motionsig_cli.rng import trial_rng
from motionsig_cli.surveillance.clock import ClockModel, psi
from motionsig_cli.surveillance.clock_tracking import (
    RateKalmanClock,
    ReportClock,
    clock_error_recursion,
    position_update,
    pseudo_measurement,
)
from motionsig_cli.surveillance.multilateration import (
    C_FT_PER_NS_EXACT,
    C_FT_PER_NS_REPORT,
    C_M_PER_NS,
    R_EARTH_KM,
    RSAT_GEO_KM,
    RSAT_REPORT_RE,
    GeometryError,
    GeometryMetrics,
    check_geometry,
    directions,
    ecef,
    enu_basis,
    ls_position_clock,
    metrics,
    zenith_deg,
)

EXAMPLES = ("I", "II")
TABLE_SIGMA_NS = 50.0
TABLE_SIGMA0_NS = (5.0, 50.0, 500.0)
CONE_DEG = 45.0
"""Visibility cone half-angle about the local vertical (§4.6): a warning, not an error."""
MIN_ALT_KM, MAX_ALT_KM = -1.0, 100.0
"""Aircraft altitudes accepted (below −1 km the aircraft is inside the Earth)."""
COND_WARN = 1e3
"""cond(U) above this: a legal but nearly singular geometry (spec §7: warn)."""
MAX_SPEED_MPS = 1000.0
"""Largest aircraft speed accepted by the simulator."""
MAX_WORK = 20_000_000
"""Largest runs × updates the simulator accepts (≈ 4 minutes on one core)."""


class Convention(StrEnum):
    """Which speed of light, orbit radius and three-satellite constant."""

    corrected = "corrected"
    report = "report"


class ParamSource(StrEnum):
    """Where β, tr, b come from: the printed Table 4.2 or the Table 4.1 geometry."""

    table = "table"
    geometry = "geometry"


def c_ft_per_ns(convention: Convention) -> float:
    """Speed of light used to turn light-ns into feet."""
    return C_FT_PER_NS_REPORT if convention is Convention.report else C_FT_PER_NS_EXACT


def default_rsat_km(convention: Convention) -> float:
    """Orbit radius: 9.235 R_E (report, fits Table 4.2) or geosynchronous (corrected)."""
    return RSAT_REPORT_RE * R_EARTH_KM if convention is Convention.report else RSAT_GEO_KM


# --- constellations ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Constellation:
    """Sub-satellite points, orbit radius and aircraft (a snapshot geometry, spec §4.4 [A]).

    Attributes:
        lat_deg, lon_deg: sub-satellite points (Table 4.1 or a user file).
        r_sat_km: orbit radius.
        aircraft: (latitude, longitude, altitude km).
        triplet: 0-based indices of the three satellites kept in an outage.
        labels: satellite names (1-based numbers of Table 4.1).
        name: for metadata.
    """

    lat_deg: tuple[float, ...]
    lon_deg: tuple[float, ...]
    r_sat_km: float
    aircraft: tuple[float, float, float] = (45.0, 120.0, 0.0)
    triplet: tuple[int, int, int] = (0, 1, 2)
    labels: tuple[str, ...] = ()
    name: str = ""

    def __post_init__(self) -> None:
        K = len(self.lat_deg)
        if K != len(self.lon_deg):
            raise ValueError("latitude and longitude lists differ in length")
        if K < 3:
            raise GeometryError(f"{K} satellite(s): at least three are needed to fix a position")
        for lat in (*self.lat_deg, self.aircraft[0]):
            if not (math.isfinite(lat) and -90.0 <= lat <= 90.0):
                raise ValueError(f"latitude {lat:g} is outside [-90, 90] degrees")
        if not all(math.isfinite(v) for v in (*self.lon_deg, self.aircraft[1], self.aircraft[2])):
            raise ValueError("longitudes and altitude must be finite")
        if not (math.isfinite(self.r_sat_km) and self.r_sat_km > R_EARTH_KM + max(self.aircraft[2], 0.0)):
            raise ValueError(
                f"satellite radius {self.r_sat_km:g} km must exceed the Earth radius and the aircraft"
            )
        if not MIN_ALT_KM <= self.aircraft[2] <= MAX_ALT_KM:
            raise ValueError(
                f"aircraft altitude {self.aircraft[2]:g} km is outside [{MIN_ALT_KM:g}, {MAX_ALT_KM:g}] km"
            )
        if len(set(self.triplet)) != 3 or not all(0 <= i < K for i in self.triplet):
            raise ValueError(f"outage satellites must be three distinct numbers in 1..{K}")
        if not self.labels:
            object.__setattr__(self, "labels", tuple(str(i + 1) for i in range(K)))

    @property
    def K(self) -> int:
        return len(self.lat_deg)

    def sats_km(self) -> np.ndarray:
        """(K, 3) satellite positions [km]."""
        return ecef(np.array(self.lat_deg), np.array(self.lon_deg), self.r_sat_km)

    def aircraft_km(self) -> np.ndarray:
        """Aircraft position [km]."""
        lat, lon, alt = self.aircraft
        return ecef(lat, lon, R_EARTH_KM + alt)

    def directions(self, subset: Sequence[int] | None = None) -> np.ndarray:
        """U: unit vectors from the satellites (all, or ``subset``) to the aircraft."""
        sats = self.sats_km()
        if subset is not None:
            sats = sats[list(subset)]
        return directions(sats, self.aircraft_km())[0]

    def zenith_deg(self) -> np.ndarray:
        """Zenith angle of each satellite at the aircraft."""
        return zenith_deg(self.directions(), enu_basis(self.aircraft[0], self.aircraft[1])[2])

    def check_horizon(self) -> None:
        """Every satellite above the aircraft's horizon (spec §7)."""
        z = self.zenith_deg()
        below = [self.labels[i] for i in np.flatnonzero(z > 90.0)]
        if below:
            raise GeometryError(f"satellite(s) {', '.join(below)} below the aircraft's horizon")

    def check_all(self) -> None:
        """All satellites fix position and clock (K ≥ 4, β > 0, rank 3)."""
        check_geometry(self.directions(), labels="all satellites")

    def check_triplet(self) -> None:
        """The outage triplet fixes a position given the clock (rank 3)."""
        names = ",".join(self.labels[i] for i in self.triplet)
        check_geometry(self.directions(self.triplet), labels=f"satellites {names}", need_clock=False)

    def warnings(self) -> list[str]:
        """Legal but noteworthy geometry: satellites outside the 45° cone, nearly singular subsets."""
        z = self.zenith_deg()
        out = []
        wide = [f"{self.labels[i]} ({z[i]:.1f} deg)" for i in np.flatnonzero(z > CONE_DEG)]
        if wide:
            shown = ", ".join(wide[:5]) + (f" and {len(wide) - 5} more" if len(wide) > 5 else "")
            out.append(f"satellite(s) {shown} outside the {CONE_DEG:g} deg cone")
        for label, subset in (("all satellites", None), ("the outage satellites", self.triplet)):
            m = metrics(self.directions(subset))
            if float(m.cond) > COND_WARN:
                out.append(
                    f"{label} are nearly singular (cond(U) = {float(m.cond):.3g}, tr = {float(m.tr):.3g})"
                )
        return out

    def check(self) -> list[str]:
        """Observability errors (raised) and visibility warnings (returned), spec §7."""
        self.check_horizon()
        self.check_all()
        self.check_triplet()
        return self.warnings()


def table_4_1() -> dict[str, tuple[tuple[float, ...], tuple[float, ...]]]:
    """Table 4.1 sub-satellite points by example: (latitudes, longitudes)."""
    t = load("atc10_table4_1.csv")
    ex = t.column("example")
    lat, lon = t.numeric("latitude_deg"), t.numeric("longitude_deg")
    return {
        e: (
            tuple(float(v) for v, x in zip(lat, ex, strict=True) if x == e),
            tuple(float(v) for v, x in zip(lon, ex, strict=True) if x == e),
        )
        for e in EXAMPLES
    }


def example(name: str, *, r_sat_km: float, triplet: tuple[int, int, int] = (0, 1, 2)) -> Constellation:
    """Example I or II of §4.6 at orbit radius ``r_sat_km`` with the aircraft at (45°, 120°, 0)."""
    if name not in EXAMPLES:
        raise ValueError(f"unknown example {name!r}; expected I or II")
    lat, lon = table_4_1()[name]
    return Constellation(lat, lon, r_sat_km, triplet=triplet, name=f"Example {name}")


# --- Table 4.2 --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ConstellationParams:
    """β, tr, b (all satellites) and tr3, b3 (outage triplet), c = 1 units, with where they came from."""

    beta: float
    tr: float
    b: float
    tr3: float
    b3: float
    source: str


TABLE_4_2_KEYS = ("beta", "tr_all", "tr_123", "b_all", "b_123")


def table_4_2_printed() -> dict[str, dict[str, float]]:
    """Table 4.2 as printed, by example."""
    t = load("atc10_table4_2.csv")
    cols = {k: t.numeric(k) for k in TABLE_4_2_KEYS}
    return {e: {k: float(cols[k][i]) for k in TABLE_4_2_KEYS} for i, e in enumerate(t.column("example"))}


def geometry_params(con: Constellation) -> dict[str, float]:
    """β, tr, b for all satellites; tr, b (corrected) and b_literal for the triplet; GDOP."""
    m_all: GeometryMetrics = metrics(con.directions())
    m3: GeometryMetrics = metrics(con.directions(con.triplet))
    return {
        "beta": float(m_all.beta),
        "tr_all": float(m_all.tr),
        "tr_123": float(m3.tr),
        "b_all": float(m_all.b),
        "b_123_correct": float(m3.b),
        "b_123_literal": float(m3.b_literal),
        "gdop": float(m_all.gdop),
    }


def constellation_params(
    name: str,
    convention: Convention,
    source: ParamSource,
    *,
    r_sat_km: float | None = None,
) -> ConstellationParams:
    """The constants behind Table 4.3 and Figs 4.2/4.3.

    ``table``: the printed Table 4.2; in the corrected convention b3 is replaced by the correct
    1'(UU')⁻¹1 at the radius that reproduces Table 4.2 (9.235 R_E) — the spec's corrected curve values.
    ``geometry``: computed from Table 4.1 at ``r_sat_km`` (default by convention), with b3 literal
    (report) or correct (corrected).
    """
    if source is ParamSource.table:
        p = table_4_2_printed()[name]
        b3 = p["b_123"]
        src = "Table 4.2 as printed"
        if convention is Convention.corrected:
            g = geometry_params(example(name, r_sat_km=RSAT_REPORT_RE * R_EARTH_KM))
            b3 = g["b_123_correct"]
            src += "; b3 = 1'(UU')^-1 1 recomputed at 9.235 R_E"
        return ConstellationParams(p["beta"], p["tr_all"], p["b_all"], p["tr_123"], b3, src)
    rs = default_rsat_km(convention) if r_sat_km is None else r_sat_km
    g = geometry_params(example(name, r_sat_km=rs))
    b3 = g["b_123_literal" if convention is Convention.report else "b_123_correct"]
    kind = "literal 1'(U'U)^-1 1, ECEF" if convention is Convention.report else "1'(UU')^-1 1"
    return ConstellationParams(
        g["beta"], g["tr_all"], g["b_all"], g["tr_123"], b3, f"Table 4.1 geometry at {rs:.6g} km; b3 = {kind}"
    )


def fit_orbit_radius(names: Sequence[str] = EXAMPLES, lo: float = 5.0, hi: float = 15.0) -> float:
    """The orbit radius (Earth radii) that best fits Table 4.2: least squares in the log of all five
    printed constants (b3 as the literal 1'(U'U)⁻¹1) of the given examples (spec §4.2 finding)."""
    from scipy.optimize import minimize_scalar

    printed = table_4_2_printed()

    def cost(ratio: float) -> float:
        s = 0.0
        for n in names:
            g = geometry_params(example(n, r_sat_km=ratio * R_EARTH_KM))
            g["b_123"] = g["b_123_literal"]
            s += sum(math.log(g[k] / printed[n][k]) ** 2 for k in TABLE_4_2_KEYS)
        return s

    return float(minimize_scalar(cost, bounds=(lo, hi), method="bounded", options={"xatol": 1e-6}).x)


# --- timelines and the analytic curves ---------------------------------------------------------------


@dataclass(frozen=True)
class Timeline:
    """Epochs n = 0..epochs; all satellites up to N = ``outage_start``; only the triplet for
    n = N+1..N+M; all satellites again afterwards (continue, or restart by least squares)."""

    epochs: int = 160
    outage_start: int = 100
    outage_length: int = 60
    reinit_after_outage: bool = False

    def __post_init__(self) -> None:
        if self.epochs < 0:
            raise ValueError("the number of updates must be >= 0")
        if self.outage_start < 0 or self.outage_length < 0:
            raise ValueError("outage start and length must be >= 0")
        if self.outage_length and self.outage_start + self.outage_length > self.epochs:
            raise ValueError(
                f"the outage (epochs {self.outage_start + 1}..{self.outage_start + self.outage_length}) "
                f"is longer than the run (epochs 0..{self.epochs})"
            )

    @property
    def n(self) -> np.ndarray:
        return np.arange(self.epochs + 1)

    def outage(self) -> np.ndarray:
        """True at epochs with only the three outage satellites."""
        n = self.n
        return (n > self.outage_start) & (n <= self.outage_start + self.outage_length)

    def reinit(self) -> np.ndarray:
        """True at least-squares restarts (epoch 0; the first epoch after the outage if requested)."""
        r = self.n == 0
        if self.reinit_after_outage and self.outage_length:
            r |= self.n == self.outage_start + self.outage_length + 1
        return r


@dataclass(frozen=True)
class RmsCurves:
    """RMS position error [ft] against epoch for several σ0 (rows) — Figs 4.2/4.3."""

    n: np.ndarray
    sigma0: np.ndarray
    rms_tracking: np.ndarray
    rms_ls: np.ndarray
    gain: np.ndarray
    clock_var: np.ndarray
    outage: np.ndarray


def rms_curves(
    params: ConstellationParams,
    sigma: float,
    sigma0: Sequence[float],
    timeline: Timeline,
    c_ft: float,
    *,
    steady_gain: bool = False,
) -> RmsCurves:
    """√E‖ξ_pn‖² by the exact recursion (spec §2.7) and the no-tracking LS value (NaN in an outage)."""
    s0 = np.asarray(sigma0, dtype=float)
    out = timeline.outage()
    beta = np.full(out.shape, params.beta)
    tr = np.where(out, params.tr3, params.tr)
    b = np.where(out, params.b3, params.b)
    g = psi((8.0 / 27.0) * s0**2 * params.beta / sigma**2) if steady_gain else None
    rec = clock_error_recursion(sigma, s0, beta, ~out, reinit=timeline.reinit(), gain=g)
    rms = c_ft * np.sqrt(sigma**2 * tr + rec.V * b)  # (4.5.35)
    ls = np.where(out, np.nan, c_ft * sigma * math.sqrt(params.tr + params.b / params.beta))
    return RmsCurves(timeline.n, s0, rms, np.broadcast_to(ls, rms.shape), rec.gain, rec.V, out)


# --- Monte Carlo -----------------------------------------------------------------------------------------

ESTIMATORS = ("none", "report", "kf2")
MAX_RUNS = 50_000


@dataclass(frozen=True)
class SimulationConfig:
    """A Monte Carlo of the estimators on nonlinear TOA measurements (spec §6.1).

    Attributes:
        constellation: the geometry (snapshot; satellites do not move).
        sigma: TOA error σ [ns]; Gaussian.
        sigma0: clock scale σ0 [ns] of the model the trackers assume (σ1 = σ2 = σ0, ρ = 1).
        rho: the true clock's flicker exponent (ρ < 1: the trackers' model is wrong, spec §6.4).
        timeline: epochs and outage.
        estimators: any of ``none`` (LS each epoch), ``report`` (the report's tracker), ``kf2``.
        velocity_enu: constant aircraft velocity [m/s] east/north/up (default static).
        tau_bar_s: pulse interval τ̄ [s] (only moves the aircraft between pulses).
        init_offset_km: per-axis standard deviation of the initial guess p*_0 [km].
        relinearise: extra linearisations per epoch at the new estimate (same gain).
        steady_gain: use the constant gain ψ(α) from n = 1 (the report's shortcut).
    """

    constellation: Constellation
    sigma: float = TABLE_SIGMA_NS
    sigma0: float = 50.0
    rho: float = 1.0
    timeline: Timeline = field(default_factory=Timeline)
    estimators: tuple[str, ...] = ESTIMATORS
    velocity_enu: tuple[float, float, float] = (0.0, 0.0, 0.0)
    tau_bar_s: float = 1.0
    init_offset_km: float = 50.0
    relinearise: int = 2
    steady_gain: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.sigma) and self.sigma > 0):
            raise ValueError("sigma must be a finite number > 0")
        if not (math.isfinite(self.sigma0) and self.sigma0 >= 0):
            raise ValueError("sigma0 must be a finite number >= 0")
        if not 0.5 < self.rho <= 1.0:
            raise ValueError(f"rho = {self.rho:g} is outside (1/2, 1]")
        bad = [e for e in self.estimators if e not in ESTIMATORS]
        if bad or not self.estimators:
            raise ValueError(f"unknown estimator(s) {bad}; choose from {', '.join(ESTIMATORS)}")
        if self.relinearise < 0 or self.init_offset_km < 0 or not self.tau_bar_s > 0:
            raise ValueError("relinearise and init offset must be >= 0, tau_bar > 0")
        if self.rho < 1.0 and self.timeline.epochs > 5000:
            raise ValueError("rho < 1 clocks are generated by Cholesky: at most 5000 updates")
        if (
            not all(math.isfinite(v) for v in self.velocity_enu)
            or math.hypot(*self.velocity_enu) > MAX_SPEED_MPS
        ):
            raise ValueError(f"aircraft speed must be finite and at most {MAX_SPEED_MPS:g} m/s")


@dataclass(frozen=True)
class SimulationResult:
    """Per-epoch RMS error [ft] and its standard error for each estimator, with the analytic curve."""

    n: np.ndarray
    K: np.ndarray
    rms: dict[str, np.ndarray]
    se: dict[str, np.ndarray]
    analytic_report: np.ndarray
    analytic_ls: np.ndarray
    runs: int


def _truth_light_ns(con: Constellation, cfg: SimulationConfig) -> tuple[np.ndarray, np.ndarray]:
    """Satellites (K, 3) and aircraft track (E, 3) in light-ns."""
    to_lns = 1e3 / C_M_PER_NS
    sats = con.sats_km() * to_lns
    p0 = con.aircraft_km() * to_lns
    v = np.asarray(cfg.velocity_enu) @ enu_basis(con.aircraft[0], con.aircraft[1]) / C_M_PER_NS  # m/s → lns/s
    n = cfg.timeline.n
    return sats, p0 + (n * cfg.tau_bar_s)[:, None] * v


def check_track(cfg: SimulationConfig) -> None:
    """The moving aircraft stays between −1 and 100 km altitude and sees every satellite to the end."""
    sats, truth = _truth_light_ns(cfg.constellation, cfg)
    alt_km = np.linalg.norm(truth, axis=-1) * C_M_PER_NS / 1e3 - R_EARTH_KM
    if alt_km.min() < MIN_ALT_KM or alt_km.max() > MAX_ALT_KM:
        raise ValueError(
            f"the aircraft track leaves [{MIN_ALT_KM:g}, {MAX_ALT_KM:g}] km altitude "
            f"(from {alt_km.min():.3g} to {alt_km.max():.3g} km)"
        )
    up_last = truth[-1] / np.linalg.norm(truth[-1])
    if np.any(zenith_deg(directions(sats, truth[-1])[0], up_last) > 90.0):
        raise GeometryError("a satellite sets below the aircraft's horizon during the run")


def analytic_curve(cfg: SimulationConfig) -> tuple[np.ndarray, np.ndarray]:
    """The recursion's RMS [ft, exact c] for the configured tracker at the true (initial) geometry,
    and the no-tracking LS value (NaN in an outage)."""
    con = cfg.constellation
    m_all, m3 = metrics(con.directions()), metrics(con.directions(con.triplet))
    params = ConstellationParams(
        float(m_all.beta), float(m_all.tr), float(m_all.b), float(m3.tr), float(m3.b), "simulation geometry"
    )
    c = rms_curves(
        params, cfg.sigma, [cfg.sigma0], cfg.timeline, C_FT_PER_NS_EXACT, steady_gain=cfg.steady_gain
    )
    return c.rms_tracking[0], c.rms_ls[0]


def _draws(
    cfg: SimulationConfig, seed: int, runs: range, K: int, chol: np.ndarray | None
) -> dict[str, np.ndarray]:
    """Every random number of runs ``runs``: run r draws from ``trial_rng(seed, r)`` only, in a fixed order."""
    E = cfg.timeline.epochs + 1
    clock = ClockModel(cfg.sigma0, cfg.sigma0, cfg.rho)
    tau0, x, eps, off = [], [], [], []
    for r in runs:
        g = trial_rng(seed, r)
        tau0.append(g.uniform(-1e6, 1e6))  # τ_0 unknown: ±1 ms [ns]
        x.append(
            clock.sample(g, E - 1)
            if chol is None
            else np.concatenate([[0.0], chol @ g.standard_normal(E - 1)])
        )
        eps.append(g.standard_normal((E, K)) * cfg.sigma)
        off.append(g.standard_normal(3) * cfg.init_offset_km)
    return {"tau0": np.array(tau0), "x": np.array(x), "eps": np.array(eps), "off": np.array(off)}


# Cost model of one task (seconds; measured on one core, used only to size the tasks — never a clock):
# per run and update, each estimator costs RUN_UPDATE_SECONDS[e] (the trackers scale with the number of
# linearisations); the vectorised loop over updates costs a fixed UPDATE_OVERHEAD_SECONDS per update and
# task (plus TRACKER_OVERHEAD_SECONDS per tracker), whatever the number of runs in the task.
RUN_UPDATE_SECONDS = {"none": 2.6e-6, "report": 2.0e-6, "kf2": 3.4e-6}
UPDATE_OVERHEAD_SECONDS = 2e-4
TRACKER_OVERHEAD_SECONDS = 3.5e-4
CHOLESKY_FLOP_SECONDS = 1e-9
AMORTISE = 2.0
"""A task does at least this many times its fixed cost in per-run work (vectorisation pays off)."""
MAX_TASK_RUNS = 2000
MAX_TASK_VALUES = 16_000_000
"""Largest runs x updates x (satellites + 2) random numbers held by one task (memory bound)."""


def _uses_cholesky(cfg: SimulationConfig) -> bool:
    return cfg.rho != 1.0 and cfg.sigma0 != 0.0


def clock_factor(cfg: SimulationConfig) -> np.ndarray | None:
    """The Cholesky factor of a ρ < 1 clock's covariance (None for ρ = 1 or a perfect clock).

    Computed once, where the run is planned, and shipped with the task function: LAPACK's blocked
    Cholesky gives different last bits for different BLAS thread counts (a Dask worker runs with
    OPENBLAS_NUM_THREADS=1), so a factor computed on each worker would break the byte-identical
    output. The product of the factor with a vector does not depend on the thread count.
    """
    if not _uses_cholesky(cfg):
        return None
    return ClockModel(cfg.sigma0, cfg.sigma0, cfg.rho).cholesky(cfg.timeline.epochs)


def task_function(cfg: SimulationConfig, seed: int) -> Callable[[range], dict[str, np.ndarray]]:
    """The picklable task function of a run: :func:`simulate_runs` with the configuration, the seed and
    the clock's Cholesky factor bound."""
    return functools.partial(simulate_runs, cfg, seed, chol=clock_factor(cfg))


def runs_per_task(cfg: SimulationConfig) -> int:
    """Runs per task, from the cost model only (never from a clock or the number of workers): each task
    is worth ≥ :func:`~motionsig_cli.engine.min_task_seconds` and ≥ ``AMORTISE`` × its fixed cost of
    per-run work, within the memory bound."""
    E = cfg.timeline.epochs + 1
    trackers = sum(1 for e in cfg.estimators if e != "none")
    relin = (1 + cfg.relinearise) / 3.0  # the costs were measured with 3 linearisations per update
    per_update = sum(RUN_UPDATE_SECONDS[e] * (1.0 if e == "none" else relin) for e in cfg.estimators)
    per_run = E * per_update
    if _uses_cholesky(cfg):
        per_run += CHOLESKY_FLOP_SECONDS * float(E - 1) ** 2
    fixed = E * (UPDATE_OVERHEAD_SECONDS + TRACKER_OVERHEAD_SECONDS * trackers)
    # the floor does not scale with $MOTIONSIG_MIN_TASK_SECONDS: every task ships the clock's Cholesky
    # factor (up to ~200 MB), so one-run tasks in tests would cost minutes
    floor = math.ceil(AMORTISE * fixed / per_run)
    memory = max(1, MAX_TASK_VALUES // (E * (cfg.constellation.K + 2)))
    return int(max(1, min(MAX_TASK_RUNS, memory, max(floor, trials_per_task(per_run)))))


def simulation_tasks(cfg: SimulationConfig, runs: int, *, chunk: int | None = None) -> list[range]:
    """Check the run (limits, geometry, track) and split runs 0..runs−1 into tasks of
    :func:`runs_per_task` runs (or ``chunk``)."""
    if runs < 1:
        raise ValueError("the number of Monte Carlo runs must be >= 1")
    if runs * (cfg.timeline.epochs + 1) > MAX_WORK:
        raise ValueError(f"runs x updates = {runs * (cfg.timeline.epochs + 1):,} exceeds {MAX_WORK:,}")
    cfg.constellation.check()
    check_track(cfg)
    if runs > MAX_RUNS:
        raise ValueError(f"{runs} runs: at most {MAX_RUNS} (per-run errors are kept for an order-free sum)")
    return tasks_of(runs, runs_per_task(cfg) if chunk is None else chunk)


def simulate_runs(
    cfg: SimulationConfig, seed: int, runs: range, *, chol: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """The task function: squared position errors [ft²], (len(runs), epochs + 1) per estimator, of runs
    ``runs`` (run r draws from ``trial_rng(seed, r)`` only, so a run's errors do not depend on the task
    it is in). Module-level and pure: it runs in worker processes and on Dask workers. ``chol``: the
    clock's Cholesky factor (:func:`clock_factor`; computed here when a ρ < 1 run does not pass it)."""
    con = cfg.constellation
    tl = cfg.timeline
    E = tl.epochs + 1
    out, reinit = tl.outage(), tl.reinit()
    sats, truth = _truth_light_ns(con, cfg)
    K = con.K
    idx_all, idx3 = np.arange(K), np.array(con.triplet)
    if chol is None:
        chol = clock_factor(cfg)
    g_steady = None
    if cfg.steady_gain:
        g_steady = np.asarray(
            psi((8.0 / 27.0) * cfg.sigma0**2 * float(metrics(con.directions()).beta) / cfg.sigma**2)
        )
    R = len(runs)
    e2 = {e: np.empty((R, E)) for e in cfg.estimators}
    d = _draws(cfg, seed, runs, K, chol)
    p_guess = truth[0] + d["off"] * (1e3 / C_M_PER_NS)  # km → light-ns
    trackers: dict[str, ReportClock | RateKalmanClock] = {}
    if "report" in cfg.estimators:
        trackers["report"] = ReportClock(cfg.sigma, cfg.sigma0, steady_gain=g_steady)
    if "kf2" in cfg.estimators:
        trackers["kf2"] = RateKalmanClock(cfg.sigma, cfg.sigma0)
    p_hat: dict[str, np.ndarray] = {}
    for n in range(E):
        idx = idx3 if out[n] else idx_all
        S = sats[idx]
        rng_true = np.linalg.norm(truth[n] - S, axis=-1)
        T = d["tau0"][:, None] + d["x"][:, n, None] + rng_true[None, :] + d["eps"][:, n, idx]
        est_p: dict[str, np.ndarray] = {}
        if n == 0 or ("none" in cfg.estimators and not out[n]):
            start_p = p_guess if n == 0 else p_hat.get("none", p_hat.get("report", p_guess))
            _, p_ls, _ = ls_position_clock(T, S, start_p)
            if "none" in cfg.estimators:
                est_p["none"] = p_ls
        if n == 0:
            pm = pseudo_measurement(T, S, p_ls)
            for name, tr in trackers.items():
                tr.reinit(pm["y"], pm["beta"])
                est_p[name] = position_update(pm, p_ls, pm["y"])  # τ̂_0 = y_0 (4.5.3)
        else:
            for name, tr in trackers.items():
                p_star = p_hat[name]
                if reinit[n] and name == "report":
                    _, p_ls, _ = ls_position_clock(T, S, p_star)
                    pm = pseudo_measurement(T, S, p_ls)
                    tr.reinit(pm["y"], pm["beta"])
                    est_p[name] = position_update(pm, p_ls, pm["y"])
                    continue
                for _ in range(1 + cfg.relinearise):
                    pm = pseudo_measurement(T, S, p_star)
                    beta = None if out[n] else pm["beta"]
                    p_star = position_update(pm, p_star, tr.estimate(pm["y"], beta))
                tr.commit(pm["y"], beta)
                est_p[name] = p_star
        if "none" in cfg.estimators and out[n]:
            est_p["none"] = np.full((R, 3), np.nan)
        for name, p in est_p.items():
            if name != "none" or not out[n]:
                p_hat[name] = p
            e2[name][:, n] = np.sum((p - truth[n]) ** 2, axis=-1) * C_FT_PER_NS_EXACT**2
    return e2


def combine_runs(cfg: SimulationConfig, parts: Sequence[dict[str, np.ndarray]]) -> SimulationResult:
    """The reduction: the tasks' per-run errors stacked in task order (= run order), then mean and
    standard error over all runs at once — the same numbers whatever the tasks or workers."""
    con, tl = cfg.constellation, cfg.timeline
    E = tl.epochs + 1
    runs = sum(len(next(iter(p.values()))) for p in parts)
    rms, se = {}, {}
    for e in cfg.estimators:
        e2 = np.concatenate([p[e] for p in parts], axis=0)
        m = e2.mean(axis=0)
        var = e2.var(axis=0, ddof=1) if runs > 1 else np.full(E, np.nan)
        rms[e] = np.sqrt(m)
        with np.errstate(invalid="ignore", divide="ignore"):
            se[e] = np.sqrt(np.maximum(var, 0.0) / runs) / (2.0 * rms[e])  # delta method
    ana, ls = analytic_curve(cfg)
    Kn = np.where(tl.outage(), 3, con.K)
    return SimulationResult(tl.n, Kn, rms, se, ana, ls, runs)


def simulate(
    cfg: SimulationConfig,
    runs: int,
    seed: int,
    *,
    chunk: int | None = None,
    on_progress: Callable[[int], None] | None = None,
    engine: Engine | None = None,
) -> SimulationResult:
    """Monte Carlo of the configured estimators (spec §6.1), vectorised over the runs of a task.

    Measurements: T̂_ni − nτ̄ = τ_0 + x_n + ‖p_n − S_i‖/c + ε_ni (eq 4.2.2, η = 0, exact c). Run r uses
    only ``trial_rng(seed, r)`` and the per-run errors are reduced in run order, so results depend on
    neither the chunk size (default :func:`runs_per_task`) nor where ``engine`` runs the tasks (default:
    in this process).
    """
    tasks = simulation_tasks(cfg, runs, chunk=chunk)
    parts = run_tasks(
        task_function(cfg, seed),
        tasks,
        engine or Engine(),
        sizes=[len(t) for t in tasks],
        progress=on_progress,
        identity={"command": "satellite_tracking.simulate", "config": repr(cfg), "runs": runs, "seed": seed,
                  "runs_per_task": len(tasks[0])},
    )  # fmt: skip
    return combine_runs(cfg, parts)


# --- Table 4.3 -------------------------------------------------------------------------------------------


def table_4_3_printed() -> list[dict[str, float | str]]:
    """Table 4.3 as printed."""
    t = load("atc10_table4_3.csv")
    cols = ("sigma_ns", "sigma0_ns", "alpha", "psi", "e0_ft", "eN_ft", "eN1_ft")
    num = {c: t.numeric(c) for c in cols}
    return [
        {"example": ex, **{c: float(num[c][i]) for c in cols}} for i, ex in enumerate(t.column("example"))
    ]


def time_to_exceed(curve: np.ndarray, n: np.ndarray, start: int, level: float) -> int | None:
    """Outage epochs m = n − N until the RMS first exceeds ``level`` (None if it never does)."""
    after = (n > start) & (curve > level)
    hit = np.flatnonzero(after)
    return int(n[hit[0]] - start) if hit.size else None


__all__ = [
    "ESTIMATORS",
    "EXAMPLES",
    "Constellation",
    "ConstellationParams",
    "Convention",
    "ParamSource",
    "RmsCurves",
    "SimulationConfig",
    "SimulationResult",
    "Timeline",
    "analytic_curve",
    "c_ft_per_ns",
    "check_track",
    "clock_factor",
    "combine_runs",
    "constellation_params",
    "default_rsat_km",
    "example",
    "fit_orbit_radius",
    "geometry_params",
    "rms_curves",
    "runs_per_task",
    "simulate",
    "simulate_runs",
    "simulation_tasks",
    "table_4_1",
    "table_4_2_printed",
    "table_4_3_printed",
    "task_function",
    "time_to_exceed",
]
