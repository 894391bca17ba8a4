"""`make bench`: motionsig's batched LMP filter bank vs FilterPy running the identical bank.

Workload (Fig 4 of the mode-signature paper, 47th IEEE CDC, Cancún, 2008): 50 trials × 4 R values × 187 filters (1 H0 + 93 candidates ×
{cos, sin}) × 1600 steps (T = 0.05 s, 80 s) = 59.84 M filter-steps.

1. Correctness gate: for a handful of filters and one record, FilterPy's cumulative
   ½ Σ ν²/S (from ``kf.y``, ``kf.S`` after each update) must equal ours to 1e-8 relative.
2. Timing (best of 3 on both sides): motionsig runs the whole workload. FilterPy runs a slice (filters × steps of one record)
   and is extrapolated linearly in filter-steps: it has no way to share the Riccati recursion
   across trials, so every trial costs it the same. Both run in this process, side by side.
3. Where JAX imports (the optional ``bench-jax`` extra): the same bank written as ``jit(vmap(lax.scan))``
   (one scan over time per filter, the covariance recursion shared by the trials inside it, the Joseph
   update and the re-symmetrised prediction of :mod:`motionsig_cli.filters.kalman`), float64
   (``jax_enable_x64``), against motionsig on the same workload, side by side on ONE core: a child
   process pinned to one CPU, XLA with ``--xla_cpu_multi_thread_eigen=false
   intra_op_parallelism_threads=1`` and one BLAS thread for NumPy. Correctness gate: J0, J_cos and
   J_sin at every horizon equal ours to 1e-8 relative. XLA's compile time is reported apart from the run
   time (best of 3 each side).

Writes ``benchmarks/results/bench_kf_bank.csv`` (layout: ``benchlib.COLUMNS``) and prints a summary.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
from collections.abc import Callable
from typing import Any

import numpy as np
from benchlib import best_of, filterpy_row, gate, measured_row, publish

from motionsig_cli.detection.lmp import LMPConfig, candidate_grid, lmp_detect
from motionsig_cli.filters.kalman import innovation_costs, riccati
from motionsig_cli.models.vehicle import Vehicle1D, amplitude_column, transition_h0
from motionsig_cli.modesig.lmp1d import simulate_trials
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes
from motionsig_cli.signals.signature import replica_bank

TRIALS, RS, N, M_RHO = 50, (1e-1, 1e-2, 1e-3, 1e-5), 1600, 20
HORIZONS = [200 * j for j in range(1, 9)]
ONE_CORE_FLAG = "--one-core-jax"  # the child process of step 3
REPEATS = 3  # best of 3 on both sides (the machine is shared; minima are the least disturbed)
CHIPS = to_bipolar(corrected_codes()).astype(float)


def h1_bank(veh: Vehicle1D, cfg: LMPConfig) -> tuple[Callable[[int], np.ndarray], np.ndarray]:
    cands = candidate_grid(3, 31, M_RHO, cfg)
    zc, zs, dc, ds = replica_bank(CHIPS, cands.mode, cands.tau, cands.f_c, veh.T, M_RHO, N)
    g = np.concatenate([amplitude_column(veh, zc, dc), amplitude_column(veh, zs, ds)])
    F = np.zeros((g.shape[0], 5, 5))
    F[:, :4, :4] = transition_h0(veh)
    F[:, 4, 4] = 1.0

    def F_at(k: int) -> np.ndarray:
        F[:, 1, 4] = g[:, k]
        return F

    return F_at, g


def filterpy_costs(
    veh: Vehicle1D, cfg: LMPConfig, g_rows: np.ndarray, y: np.ndarray, n_steps: int
) -> np.ndarray:
    """FilterPy KalmanFilter, one object per filter, same model: cumulative ½ Σ ν²/S per filter."""
    from filterpy.kalman import KalmanFilter

    base = np.zeros((5, 5))
    base[:4, :4] = transition_h0(veh)
    base[4, 4] = 1.0
    out = np.empty(len(g_rows))
    for i, g in enumerate(g_rows):
        kf = KalmanFilter(dim_x=5, dim_z=1)
        kf.x = np.zeros((5, 1))
        kf.P = cfg.P0 * np.eye(5)
        kf.H = np.array([[1.0, 0, 0, 0, 0]])
        kf.R = np.array([[cfg.c_r * veh.R]])
        kf.Q = np.diag([*cfg.Q0, cfg.Q_a])
        J = 0.0
        for k in range(n_steps):
            kf.update(y[k])
            J += 0.5 * float(kf.y[0, 0] ** 2 / kf.S[0, 0])
            F = base.copy()
            F[1, 4] = g[k]
            kf.F = F
            kf.predict()
        out[i] = J
    return out


def main() -> int:
    cfg = LMPConfig()
    veh = Vehicle1D(R=1e-3)
    y1, _ = simulate_trials(veh, CHIPS, M_RHO, 1.0, N, 1, [0])

    # 1. correctness gate
    F_at, g = h1_bank(veh, cfg)
    Q1, R_kf = np.diag([*cfg.Q0, cfg.Q_a]), np.array([[cfg.c_r * veh.R]])
    gains = riccati(F_at, np.array([[1.0, 0, 0, 0, 0]]), Q1, R_kf, cfg.P0 * np.eye(5), N, g.shape[0])
    ours = innovation_costs(F_at, np.array([[1.0, 0, 0, 0, 0]]), gains, np.zeros(5), y1, [N])[:, 0, 0]
    pick = np.array([0, 1, 57, 92, 93, 150, 185])
    ref = filterpy_costs(veh, cfg, g[pick], y1[0], N)
    rel = np.max(np.abs(ours[pick] - ref) / np.abs(ref))
    summary = f"correctness gate: max relative difference vs FilterPy over {pick.size} filters × {N} steps = {rel:.2e}"
    if not gate(summary, rel > 1e-8, "FAILED: results differ from FilterPy by more than 1e-8 relative"):
        return 1

    # 2a. motionsig, whole workload (records simulated beforehand, not timed)
    records = {R: simulate_trials(Vehicle1D(R=R), CHIPS, M_RHO, 1.0, N, 7, range(TRIALS))[0] for R in RS}

    def ours_once() -> None:
        for R in RS:
            lmp_detect(records[R], CHIPS, Vehicle1D(R=R), M_RHO, cfg, HORIZONS)

    t_ours = best_of(ours_once, REPEATS)
    filter_steps = TRIALS * len(RS) * 187 * N
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    # 2b. FilterPy, a slice: 24 filters × 1600 steps of one record
    slice_rows = g[:24]
    t_slice = best_of(lambda: filterpy_costs(veh, cfg, slice_rows, y1[0], N), REPEATS)
    row_fp = filterpy_row("FilterPy KalmanFilter", t_slice, slice_rows.shape[0] * N, filter_steps, "filter-step",
                          f"{slice_rows.shape[0]} filters x {N} steps", REPEATS)  # fmt: skip
    row_ours = measured_row(
        "motionsig batched bank", t_ours, filter_steps, "filter-step", row_fp["seconds"], REPEATS
    )
    rows = [row_ours, row_fp]
    comments = [
        f"workload: {TRIALS} trials x {len(RS)} R x 187 filters x {N} steps (Fig 4 of the mode-signature paper)",
        f"correctness: max rel diff vs FilterPy {rel:.2e}; peak RSS {peak_mb:.0f} MB",
    ]
    jax_result = one_core_vs_jax()
    if jax_result is None:
        comments.append("JAX: not installed (optional extra bench-jax), no one-core comparison")
    elif "error" in jax_result:
        print(jax_result["error"], file=sys.stderr)
        return 1
    else:
        r = jax_result
        comments.append(
            f"one core (pinned, 1 BLAS thread, XLA single-threaded): JAX {r['jax']} jaxlib {r['jaxlib']}; "
            f"max rel diff JAX vs motionsig {r['rel']:.2e}; motionsig / JAX time {r['t_ours'] / r['t_jax']:.2f}"
        )
        how1 = ", one core (pinned), 1 BLAS thread"
        rows.append(measured_row("motionsig batched bank, 1 core", r["t_ours"], filter_steps, "filter-step",
                                 row_fp["seconds"], REPEATS, how=how1, speedup=r["t_jax"] / r["t_ours"]))  # fmt: skip
        rows.append(measured_row("JAX jit(vmap(lax.scan)), 1 core", r["t_jax"], filter_steps, "filter-step",
                                 row_fp["seconds"], REPEATS, how=how1 + ", XLA single-threaded, run only "
                                 f"(compile {r['t_compile']:.2f} s apart); speedup = motionsig 1-core time / this",
                                 speedup=r["t_ours"] / r["t_jax"]))  # fmt: skip
        rows.append({"case": "JAX compile (XLA, once)", "seconds": r["t_compile"], "units": 1, "unit": "compile",
                     "how": "lower + compile of the H0 and H1 banks, 1 core"})  # fmt: skip
    publish("bench_kf_bank", comments, rows, "{case:34s} {seconds:10.2f} s  ({how})")
    print(
        f"speed-up: {row_ours['ratio_vs_filterpy']:.0f}x   peak RSS {peak_mb:.0f} MB   target: >= 500x and < 10 s"
    )
    if jax_result is not None:
        ratio = jax_result["t_ours"] / jax_result["t_jax"]
        print(f"one core: motionsig takes {ratio:.2f}x the time of JAX jit(vmap(lax.scan))   target: <= 1.5x")
    return 0


# ---------------------------------------------------------------------------------------------------
# 3. JAX, one core (a child process: the thread settings must precede the imports of numpy and jax)
# ---------------------------------------------------------------------------------------------------


def one_core_vs_jax() -> dict[str, Any] | None:
    """Run :func:`one_core_child` in a child process pinned to one CPU; None where JAX does not import."""
    try:
        import jax  # noqa: F401
    except ImportError:
        return None
    env = dict(os.environ)
    env.update(
        XLA_FLAGS="--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1",
        OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", JAX_PLATFORMS="cpu",
    )  # fmt: skip
    out = subprocess.run(
        [sys.executable, os.path.abspath(__file__), ONE_CORE_FLAG], env=env, capture_output=True, text=True
    )
    if out.returncode != 0:
        return {"error": f"the one-core JAX comparison failed:\n{out.stderr[-2000:]}"}
    return json.loads(out.stdout.strip().splitlines()[-1])


def jax_bank(n: int, amplitude: bool, hz_index: np.ndarray) -> Callable[..., Any]:
    """jit(vmap(lax.scan)) of the bank of :func:`motionsig_cli.filters.kalman.riccati` and
    :func:`~motionsig_cli.filters.kalman.innovation_costs` (H = e_0ᵀ, m = 1): one scan over time per
    filter, the trials inside it sharing its covariance recursion. With ``amplitude`` the filter's F_k is F
    with entry (1, n − 1) = g_k (eq 44's amplitude column), else F for every k.

    Returns f(g (C, N), F (n, n), Q (n, n), P0 (n, n), R (), yT (N, B)) → J at the horizons, (C, H, B).
    """
    import jax
    import jax.numpy as jnp
    from jax import lax

    eye = jnp.eye(n)

    def one_filter(g_row: Any, F: Any, Q: Any, P0: Any, R: Any, yT: Any) -> Any:
        def step(carry: Any, inp: Any) -> Any:
            x, P, J = carry
            gk, yk = inp
            S_inv = 1.0 / (P[0, 0] + R)  # S = H P Hᵀ + R, eq (47)
            K = P[:, 0] * S_inv
            nu = yk - x[0]
            J = J + 0.5 * S_inv * nu * nu  # ½ ν² / S, eq (49)
            x = x + K[:, None] * nu[None, :]
            IKH = eye.at[:, 0].add(-K)  # I − K H
            P = IKH @ P @ IKH.T + R * jnp.outer(K, K)  # Joseph form
            Fk = F.at[1, n - 1].set(gk) if amplitude else F
            x = Fk @ x
            P = Fk @ P @ Fk.T + Q
            P = 0.5 * (P + P.T)
            return (x, P, J), J

        B = yT.shape[1]
        init = (jnp.zeros((n, B)), P0, jnp.zeros(B))
        _, Js = lax.scan(step, init, (g_row, yT))
        return Js[hz_index]

    return jax.jit(jax.vmap(one_filter, in_axes=(0, None, None, None, None, None)))


def one_core_child() -> int:
    """The child of :func:`one_core_vs_jax`: motionsig and JAX side by side; prints one JSON line."""
    import time

    import jax

    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    from motionsig_cli.detection.lmp import filter_model

    cfg = LMPConfig()
    records = {R: simulate_trials(Vehicle1D(R=R), CHIPS, M_RHO, 1.0, N, 7, range(TRIALS))[0] for R in RS}
    hz_index = np.asarray(HORIZONS) - 1
    veh = Vehicle1D()
    model = filter_model(veh, cfg)
    n = model.n
    cands = candidate_grid(CHIPS.shape[0], CHIPS.shape[1], M_RHO, cfg)
    zc, zs, dc, ds = replica_bank(CHIPS, cands.mode, cands.tau, cands.f_c, veh.T, M_RHO, N, cfg.zdot)
    g = np.concatenate([amplitude_column(veh, zc, dc), amplitude_column(veh, zs, ds)])  # (2C, N)
    F1 = np.zeros((n + 1, n + 1))
    F1[:n, :n] = model.F0
    F1[n, n] = 1.0
    h0, h1 = jax_bank(n, False, hz_index), jax_bank(n + 1, True, hz_index)
    args0 = (jnp.zeros((1, N)), jnp.asarray(model.F0), jnp.asarray(model.Q0), cfg.P0 * jnp.eye(n))
    args1 = (jnp.asarray(g), jnp.asarray(F1), jnp.asarray(model.Q1), cfg.P0 * jnp.eye(n + 1))

    def inputs(R: float) -> tuple[Any, Any]:
        return jnp.asarray(cfg.c_r * Vehicle1D(R=R).R), jnp.asarray(np.ascontiguousarray(records[R].T))

    t0 = time.perf_counter()
    c0 = h0.lower(*args0, *inputs(RS[0])).compile()
    c1 = h1.lower(*args1, *inputs(RS[0])).compile()
    t_compile = time.perf_counter() - t0
    feeds = {R: inputs(R) for R in RS}

    def jax_once() -> dict[float, tuple[Any, Any]]:
        out = {R: (c0(*args0, *feeds[R]), c1(*args1, *feeds[R])) for R in RS}
        jax.block_until_ready(out)
        return out

    res: dict[str, Any] = {}

    def ours_once() -> None:
        res["ours"] = {R: lmp_detect(records[R], CHIPS, Vehicle1D(R=R), M_RHO, cfg, HORIZONS) for R in RS}

    t_ours = t_jax = float("inf")
    for _ in range(REPEATS):  # interleaved, so that both see the same machine
        t_ours = min(t_ours, best_of(ours_once, 1))
        t_jax = min(t_jax, best_of(lambda: res.update(jax=jax_once()), 1))
    rel = 0.0
    for R in RS:
        ours, (j0, j1) = res["ours"][R], res["jax"][R]
        for a, b in (
            (ours.J0, np.asarray(j0)[0].T),
            (np.concatenate([ours.J_cos, ours.J_sin]), np.swapaxes(np.asarray(j1), 1, 2)),
        ):
            rel = max(rel, float(np.max(np.abs(a - b) / np.abs(a))))
    if not rel <= 1e-8:
        print(f"FAILED: JAX differs from motionsig by {rel:.2e} relative (> 1e-8)", file=sys.stderr)
        return 1
    versions = {d: importlib_version(d) for d in ("jax", "jaxlib")}
    print(json.dumps({"t_ours": t_ours, "t_jax": t_jax, "t_compile": t_compile, "rel": rel, **versions}))
    return 0


def importlib_version(dist: str) -> str:
    import importlib.metadata

    return importlib.metadata.version(dist)


if __name__ == "__main__":
    raise SystemExit(one_core_child() if ONE_CORE_FLAG in sys.argv[1:] else main())
