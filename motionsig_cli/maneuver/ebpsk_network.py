"""Several EBPSK joint radar–communication nodes ranging one target: weighted-least-squares location from
ranges only, and the position accuracy it gives along the paper's track.

Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System* ("the paper"), say that the
trackers' positions come from a "weighted least squares" target location (§I, Fig. 1) and never give the
geometry. One monostatic radar measuring range and bearing (:mod:`motionsig_cli.maneuver.ebpsk_tracking`)
needs no least squares; several JRC nodes, each ranging the target with its own EBPSK pulse, do — this module
is that reading (a hypothesis about the paper's set-up, not something it states).

**Nodes.** S nodes at stated positions s_i (assumed: :data:`DEFAULT_NODES`, seven nodes along the literal
track), each the radar of
:class:`~motionsig_cli.maneuver.ebpsk_tracking.EbpskFrontEnd` (same waveform, budget and transmit power) at
its own position: E/N₀ from the radar equation at its own range r_i, a detection with P_D(E/N₀, ṙ_i) and a
range error ~ N(0, σ_r(E/N₀)²) — the detector-level statistics of the sample-level chain. Nodes are
independent (own pulses, own noise). A scan gives a position when at least ``min_nodes`` nodes detect
(assumed 3: two ranges leave a mirror ambiguity).

**Location** (:func:`multilaterate`). Model r_i = ‖p − s_i‖ + e_i, e_i ~ N(0, σ_i²). Closed-form start
(eq. W1): squaring, r_i² − ‖s_i‖² = −2 s_iᵀ p + ‖p‖², linear in (p, ‖p‖²) — weighted least squares with
var(r_i²) ≈ 4 r_i² σ_i² over the detected nodes. Then Gauss–Newton on Σ (r_i − ‖p − s_i‖)²/σ_i² (eq. W2):
H the rows u_iᵀ (u_i = (p − s_i)/‖p − s_i‖), p ← p + (HᵀWH)⁻¹HᵀW(r − h(p)). Covariance (HᵀWH)⁻¹ at the
solution (eq. W3), the Cramér–Rao bound of the linearised model.

**GDOP.** With equal σ, cov = σ² (Σ u_i u_iᵀ)⁻¹ and GDOP = √tr(Σ u_i u_iᵀ)⁻¹; for n ≥ 3 nodes equally spaced
in bearing around the target Σ u_i u_iᵀ = (n/2) I, so GDOP = 2/√n and σ per axis σ √(2/n) (eq. W4).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from motionsig_cli.config import ConfigError, integer

if TYPE_CHECKING:
    from motionsig_cli.maneuver.ebpsk_tracking import EbpskFrontEnd
    from motionsig_cli.maneuver.scenario import ManeuverScenario
    from motionsig_cli.tables import Table

__all__ = [
    "DEFAULT_NODES",
    "NodeNetwork",
    "gdop",
    "multilaterate",
    "network_table",
]

DEFAULT_NODES = (
    (80e3, 0.0),
    (-60e3, 160e3),
    (150e3, 170e3),
    (100e3, 360e3),
    (300e3, 350e3),
    (250e3, 540e3),
    (450e3, 540e3),
)
"""Node positions [m] (assumed): seven nodes alternating either side of the literal track, 120 km apart along
it and 80 km off it (rounded to 10 km), so that at least three are within ~200 km of every point of the track
and their lines of sight cross at wide angles."""
MAX_NODES = 64
POSITION_LIMIT = 1e8


def _check_nodes(nodes: object) -> np.ndarray:
    """``nodes`` as an (S, 2) float array of distinct finite positions within ±1e8 m, S ≥ 3 (two ranges leave
    a mirror ambiguity)."""
    try:
        arr = np.asarray(nodes, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError("nodes", nodes, "is not a list of positions x,y [m]") from None
    if arr.ndim != 2 or arr.shape[1] != 2 or not 3 <= arr.shape[0] <= MAX_NODES:
        raise ConfigError("nodes", nodes, f"is not 3 to {MAX_NODES} positions x,y [m]")
    if not np.all(np.isfinite(arr)) or np.any(np.abs(arr) > POSITION_LIMIT):
        raise ConfigError("nodes", nodes, "holds a coordinate that is not finite or beyond ±1e8 m")
    if len({tuple(p) for p in arr.tolist()}) < arr.shape[0]:
        raise ConfigError("nodes", nodes, "holds the same position twice")
    return arr


def gdop(nodes: np.ndarray, p: np.ndarray) -> np.ndarray:
    """√tr (Σ_i u_i u_iᵀ)⁻¹ at positions ``p`` (..., 2) for ``nodes`` (S, 2): the position σ (RMS of the
    two axes times √2) per unit range σ when every node has the same σ (eq. W4)."""
    d = np.asarray(p, float)[..., None, :] - np.asarray(nodes, float)
    u = d / np.linalg.norm(d, axis=-1, keepdims=True)
    info = np.einsum("...si,...sj->...ij", u, u)
    return np.sqrt(np.trace(np.linalg.inv(info), axis1=-2, axis2=-1))


def _jacobian(p: np.ndarray, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(h, H): the ranges ‖p − s_i‖ (..., S) and their gradients u_iᵀ (..., S, 2) at ``p`` (..., 2)."""
    d = p[..., None, :] - nodes
    h = np.maximum(np.linalg.norm(d, axis=-1), 1e-9)
    return h, d / h[..., None]


def multilaterate(
    ranges: np.ndarray, sigmas: np.ndarray, nodes: np.ndarray, *, iterations: int = 5
) -> tuple[np.ndarray, np.ndarray]:
    """WLS position from the ranges of S nodes (eqs W1–W3 of the module docstring), vectorised over leading
    axes.

    Args:
        ranges: (..., S) measured ranges [m]; NaN marks a node without a detection (zero weight).
        sigmas: (..., S) or broadcastable: σ of each range [m], > 0.
        nodes: (S, 2) node positions [m].
        iterations: Gauss–Newton steps after the closed-form start, ≥ 0.

    Returns:
        (xy, cov): (..., 2) and (..., 2, 2); NaN where fewer than 3 nodes detected.
    """
    s = _check_nodes(nodes)
    integer("iterations", iterations, 0, 100)
    r = np.asarray(ranges, float)
    if r.ndim < 1 or r.shape[-1] != s.shape[0]:
        raise ConfigError("ranges", f"shape {r.shape}", f"does not end in the {s.shape[0]} nodes")
    sig = np.broadcast_to(np.asarray(sigmas, float), r.shape)
    if np.any(~(sig > 0)):
        raise ConfigError("sigmas", float(sig[~(sig > 0)].flat[0]), "is not a finite number > 0")
    seen = np.isfinite(r)
    ok = seen.sum(axis=-1) >= 3
    r0 = np.where(seen, r, 0.0)
    w = np.where(seen, 1.0 / sig**2, 0.0)  # W of eq. W2, zero for missing nodes
    # W1: rows [−2 s_iᵀ, 1] (p, ‖p‖²) = r_i² − ‖s_i‖², weights 1/(4 r_i² σ_i²)
    A = np.concatenate([-2.0 * s, np.ones((s.shape[0], 1))], axis=1)  # (S, 3)
    y = r0**2 - np.sum(s * s, axis=1)
    w1 = np.where(seen, 1.0 / (4.0 * np.maximum(r0, 1.0) ** 2 * sig**2), 0.0)
    AtW = A.T * w1[..., None, :]  # (..., 3, S)
    M = AtW @ A
    M = np.where(ok[..., None, None], M, np.eye(3))
    xy = np.linalg.solve(M, (AtW @ y[..., None]))[..., :2, 0]
    for _ in range(iterations):  # W2
        h, H = _jacobian(xy, s)
        HtW = np.swapaxes(H, -1, -2) * w[..., None, :]
        info = np.where(ok[..., None, None], HtW @ H, np.eye(2))
        xy = xy + np.linalg.solve(info, HtW @ (r0 - h)[..., None])[..., 0]
    _, H = _jacobian(xy, s)
    HtW = np.swapaxes(H, -1, -2) * w[..., None, :]
    info = np.where(ok[..., None, None], HtW @ H, np.eye(2))
    cov = np.linalg.inv(info)  # W3
    cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
    return np.where(ok[..., None], xy, np.nan), np.where(ok[..., None, None], cov, np.nan)


@dataclass(frozen=True)
class NodeNetwork:
    """S EBPSK nodes ranging a track (module docstring).

    Attributes:
        front_end: the radar of every node (its position is ignored; its power, waveform and detector
            statistics are used): a prepared :class:`~motionsig_cli.maneuver.ebpsk_tracking.EbpskFrontEnd`.
        nodes: node positions [m], 3 … 64 distinct (assumed :data:`DEFAULT_NODES`).
        min_nodes: detections needed for a position, 3 … S (assumed 3).
        iterations: Gauss–Newton steps (5).
    """

    front_end: EbpskFrontEnd
    nodes: tuple[tuple[float, float], ...] = DEFAULT_NODES
    min_nodes: int = 3
    iterations: int = 5

    def __post_init__(self) -> None:
        arr = _check_nodes(self.nodes)
        object.__setattr__(self, "nodes", tuple((float(x), float(y)) for x, y in arr.tolist()))
        integer("min_nodes", self.min_nodes, 3, arr.shape[0])
        integer("iterations", self.iterations, 0, 100)

    @property
    def positions(self) -> np.ndarray:
        return np.asarray(self.nodes, float)

    def node_front_ends(self) -> list[EbpskFrontEnd]:
        """The front end moved to each node (same radar, power and statistics)."""
        import dataclasses

        return [dataclasses.replace(self.front_end, position=p) for p in self.nodes]

    def scans(self, truth: np.ndarray) -> dict[str, np.ndarray]:
        """Per node and scan (S, N): ``range``, ``enr``, ``pd``, ``sigma_range`` (the node's front end)."""
        out: dict[str, list[np.ndarray]] = {"range": [], "enr": [], "pd": [], "sigma_range": []}
        for fe in self.node_front_ends():
            st = fe.scans(truth)
            for k in out:
                out[k].append(getattr(st, k))
        return {k: np.stack(v) for k, v in out.items()}

    def bound(self, truth: np.ndarray) -> np.ndarray:
        """Position covariance (N, 2, 2) with every node detecting (eq. W3 at the truth)."""
        st = self.scans(truth)
        _, H = _jacobian(truth[:, [0, 2]], self.positions)  # (N, S, 2)
        w = 1.0 / st["sigma_range"].T ** 2  # (N, S)
        return np.linalg.inv(np.swapaxes(H, -1, -2) * w[:, None, :] @ H)

    def fix_probability(self, truth: np.ndarray) -> np.ndarray:
        """P(at least ``min_nodes`` of S independent nodes detect) per scan (N,)."""
        pd = self.scans(truth)["pd"]  # (S, N)
        dist = np.zeros((pd.shape[0] + 1, pd.shape[1]))  # Poisson-binomial, node by node
        dist[0] = 1.0
        for p in pd:
            dist[1:] = dist[1:] * (1 - p) + dist[:-1] * p
            dist[0] *= 1 - p
        return dist[self.min_nodes :].sum(axis=0)

    def measure(
        self, truth: np.ndarray, rngs: Sequence[np.random.Generator]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Positions (B, N, 2) and covariances (B, N, 2, 2) of B runs; NaN where fewer than ``min_nodes``
        nodes detect. Run b draws from ``rngs[b]``: U(0, 1) (S, N) for detection, then N(0, 1) (S, N) for the
        range errors."""
        st = self.scans(truth)
        S, N = st["pd"].shape
        u = np.stack([g.random((S, N)) for g in rngs]) if rngs else np.zeros((0, S, N))
        e = np.stack([g.standard_normal((S, N)) for g in rngs]) if rngs else np.zeros((0, S, N))
        det = u < st["pd"]
        r = np.where(det, st["range"] + e * st["sigma_range"], np.nan)  # (B, S, N)
        xy, cov = multilaterate(
            np.swapaxes(r, 1, 2), st["sigma_range"].T, self.positions, iterations=self.iterations
        )
        few = det.sum(axis=1) < self.min_nodes  # (B, N)
        return np.where(few[..., None], np.nan, xy), np.where(few[..., None, None], np.nan, cov)

    def meta(self) -> dict[str, Any]:
        return {
            "nodes_m": [list(p) for p in self.nodes],
            "min_nodes": self.min_nodes,
            "p_t_W_per_node": self.front_end.p_t,
            "location": "ranges only: closed-form start (r^2 linear in p, |p|^2), then Gauss-Newton WLS; "
            "covariance (H^T W H)^-1",
            "reading": "several JRC nodes ranging the target: a reading of the paper's 'weighted least squares "
            "location', not stated by it; node positions assumed",
        }


def network_table(sc: ManeuverScenario, net: NodeNetwork, runs: int = 200, seed: int = 2008) -> Table:
    """Per phase of the track (and over the whole track): position accuracy of the node network — the
    Monte Carlo RMS error per axis of its WLS fixes with SE, the fraction of scans with a fix, and the bound
    √(tr cov/2) with every node detecting — beside the single radar at the front end's own position (range
    and bearing, the same power: its σ_pos, RMS and median over the phase) and the paper's 100 / 200 m. Run b
    draws from ``SeedSequence(seed).spawn(runs)[b]``; the SE of the RMS is that of the mean square (scans and
    runs independent) divided by 2·RMS."""
    from motionsig_cli.maneuver.ebpsk_tracking import track_phases
    from motionsig_cli.tables import Table, make_meta

    integer("runs", runs, 2)
    integer("seed", seed, 0)
    truth = sc.truth()
    rngs = [np.random.default_rng(c) for c in np.random.SeedSequence(seed).spawn(runs)]
    xy, _ = net.measure(truth, rngs)
    err2 = 0.5 * np.sum((xy - truth[None, :, [0, 2]]) ** 2, axis=-1)  # (B, N): squared error per axis
    bound = np.sqrt(0.5 * np.trace(net.bound(truth), axis1=-2, axis2=-1))
    single = net.front_end.scans(truth).sigma_pos
    fix = net.fix_probability(truth)
    rows = []
    phases = [*track_phases(sc), ("track", 1, truth.shape[0] + 1)]
    for name, a, b in phases:
        sl = slice(a - 1, b - 1)
        e = err2[:, sl]
        got = np.isfinite(e)
        n = int(got.sum())
        ms = float(np.mean(e[got])) if n else math.nan
        se_ms = float(np.std(e[got], ddof=1) / math.sqrt(n)) if n > 1 else math.nan
        rms = math.sqrt(ms) if n else math.nan
        rows.append(
            (
                name,
                a,
                b - 1,
                float(np.mean(got)),
                float(np.mean(fix[sl])),
                rms,
                se_ms / (2 * rms) if n > 1 and rms > 0 else math.nan,
                float(np.sqrt(np.mean(bound[sl] ** 2))),
                float(np.sqrt(np.mean(single[sl] ** 2))),
                float(np.median(single[sl])),
            )
        )
    cols = (
        "phase",
        "first_scan",
        "last_scan",
        "fix_rate",
        "fix_probability",
        "rms_pos_m",
        "rms_pos_se_m",
        "bound_pos_m",
        "single_rms_sigma_pos_m",
        "single_median_sigma_pos_m",
    )
    meta = make_meta(
        "maneuver --front-end ebpsk --view network",
        preset=sc.preset,
        runs=runs,
        seed=seed,
        network=net.meta(),
        single_radar_position_m=list(net.front_end.position),
        paper_sigma_m=[100.0, 200.0],
        rms_pos="RMS over runs and the phase's scans of the position error per axis, scans with a fix",
        bound_pos="RMS over the phase's scans of sqrt(tr cov/2), every node detecting",
        single="the one radar (range and bearing) at the same power: sqrt(tr R/2) per scan",
    )
    return Table(cols, rows, meta)
