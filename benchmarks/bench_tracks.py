"""The trackers on a real ADS-B feed, in position reports per second per core, against FilterPy's
IMMEstimator and an IMM built from Stone Soup's Kalman predictor and updater.

Workload: ``tests/data/adsb/collection_quickstart.csv.gz`` (traffic's quickstart collection: 213 aircraft,
284 505 interleaved rows), read by ``read_track_records`` (cleaned, projected on one tangent plane, laid out
on each track's scan grid and cut into segments at gaps). A *report* is a measured step that a tracker
filters: the steps of every segment after its two initialising reports, missed scans (predict-only steps)
not counted. Every rate below is per report, on one core (one BLAS/OpenMP thread, process CPU time: the
machine is shared, CPU time leaves out the waits for a core; best of REPEATS).

1. Reading (for information): ``read_track_records`` on the file, timed once apart from the trackers.
2. This project, whole collection, ``TrackerConfig.tuned("aircraft")`` (IMM: CV and coordinated turns at
   ±3°/s; GLR: input estimation on the CV filter):
   - filter only: ``_run`` (two-point initialisation, ``imm_filter`` / ``input_tracker``, the IMM's
     declarations) on the batches ``track_records`` builds (built beforehand, not timed), with the tuned
     consistency checks as the command runs them, and for the IMM also without them (``consistency=None``:
     the work FilterPy and Stone Soup do);
   - end to end: ``track_records(tracks, (method,), cfg)`` (batches, filters, output table);
   - one track per call: the command ``motionsig maneuver tests/data/adsb/noisy_landing.csv --method imm`` as
     a fresh process (start-up, reading and writing the table included), child CPU time; and, for
     comparison, the same file read and tracked in this process.
3. FilterPy ``IMMEstimator`` of three ``KalmanFilter(dim_x=6, dim_z=2)`` given at every step each model's
   F(Δt), Q(Δt), the per-step R and Π(Δt) (``cfg.models(1.0).steps(dt)``), one segment at a time as it is
   used (filters and estimator built per segment, inside the timing; a missed scan: predict, μ = c̄), on the
   segments of the first SLICE_FP tracks, extrapolated per report.
4. Stone Soup (no IMM classes in 1.9: the IMM's mixing, model probabilities and combination are written here
   in NumPy around one ``KalmanPredictor``/``KalmanUpdater`` per model): CV =
   ``CombinedLinearGaussianTransitionModel`` of two ``ConstantVelocity`` (q = 1) and ``KnownTurnRate`` at
   ±3°/s (q = 5), on the 4-D state [x, ẋ, y, ẏ], with ``LinearGaussian`` measurements and the Joseph-form
   update (``use_joseph_cov=True``, as ``imm_filter`` and FilterPy); each predict takes its own timestamp (the
   Δt). These are the aircraft tuning's three models without the (zero) acceleration rows, so the estimates
   are the same. On the segments of the first SLICE_SS tracks, extrapolated per report.

Correctness gate: on the longest segment of the FilterPy slice, FilterPy's combined estimates equal
``imm_filter``'s (same Δt, models, R, initial state, checks off) to 1e-8 relative (each component scaled by
its largest magnitude, at least 1) and the model probabilities to 1e-8 absolute; so must Stone Soup's position
and velocity and model probabilities on the same segment (with its default, non-Joseph covariance update they
differ by ~3e-7 there).

Writes ``benchmarks/results/bench_tracks.csv`` (layout: ``benchlib.COLUMNS``; ``ratio_vs_filterpy``: FilterPy's
µs per report / the case's) and prints a summary. Environment variables for a quick look: BENCH_TRACKS_TRACKS
(keep the first N tracks of the collection), BENCH_TRACKS_REPEATS, BENCH_TRACKS_SLICE_FP, BENCH_TRACKS_SLICE_SS.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # one core for every tracker (set before numpy loads BLAS)
os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["MKL_NUM_THREADS"] = "1"

import importlib.metadata
import math
import resource
import subprocess
import sys
import time
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np
from benchlib import best_of, gate, write_results

from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver.record import TrackSet, read_track_records
from motionsig_cli.maneuver.record_tracking import _batch, _buckets, _noise, _run, _segments, track_records
from motionsig_cli.maneuver.study import TrackerConfig, _numerics
from motionsig_cli.models.motion import H_POS6, ModelSet, two_point_restart

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data" / "adsb" / "collection_quickstart.csv.gz"
ONE_TRACK = ROOT / "tests" / "data" / "adsb" / "noisy_landing.csv"
N_TRACKS = int(os.environ.get("BENCH_TRACKS_TRACKS", 0))  # 0: all
REPEATS = int(os.environ.get("BENCH_TRACKS_REPEATS", 3))
SLICE_FP = int(os.environ.get("BENCH_TRACKS_SLICE_FP", 20))  # tracks run through FilterPy
SLICE_SS = int(os.environ.get("BENCH_TRACKS_SLICE_SS", 5))  # tracks run through Stone Soup
CLOCK = time.process_time


def _maxrss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


# --------------------------------------------------------------------------------------------- the batches
def prepared(tracks: list, cfg: TrackerConfig) -> dict[str, Any]:
    """What ``track_records`` builds before filtering (same code): segments, noise, batches, T."""
    noise = [_noise(rec, None, cfg) for rec in tracks]
    segs, _skipped = _segments(tracks)
    order = sorted(range(len(segs)), key=lambda i: -segs[i].steps.size)
    Rs = [n[0] for n in noise]
    batches = [
        _batch([segs[i] for i in idx], tracks, Rs, None)
        for idx in _buckets(order, [segs[i].steps.size for i in order], 256)
    ]
    T = float(np.median([r.T for r in tracks if math.isfinite(r.T)] or [1.0]))
    one_r = {n[1] for n in noise} if all(n[4] for n in noise) else set()
    r_uniform = next(iter(one_r)) ** 2 if len(one_r) == 1 else None
    s_med = float(np.median([n[1] for n in noise]))
    reports = sum(int(tracks[sg.track].measured[sg.steps].sum()) for sg in segs)
    return {"noise": noise, "segs": segs, "Rs": Rs, "batches": batches, "T": T, "r_uniform": r_uniform,
            "s_med": s_med, "reports": reports}  # fmt: skip


def filter_only(prep: dict[str, Any], method: str, cfg: TrackerConfig, consistency: Any) -> None:
    """``_run`` on every batch, as ``track_records`` calls it (a segment grid: per-step Δt)."""
    for bt in prep["batches"]:
        with _numerics(prep["s_med"], prep["T"]), np.errstate(all="ignore"):
            _run(method, bt, cfg, consistency, prep["T"], False, prep["r_uniform"])


def segment_inputs(prep: dict[str, Any], tracks: list, which: list[int]) -> list[dict[str, Any]]:
    """One segment at a time (``_batch`` of one): z, R, Δt per step, x0, P0 (6-D), the step times."""
    out = []
    for i in which:
        sg = prep["segs"][i]
        bt = _batch([sg], tracks, prep["Rs"], None)
        x0, P0 = two_point_restart(bt["za"], bt["zb"], bt["dt0"], bt["Ra"], bt["Rb"], n=6)
        rec = tracks[sg.track]
        t_b = (rec.scan[sg.b] * rec.T) if rec.grid else rec.t[sg.b]
        out.append({"z": bt["z"][0], "R": bt["R"][0], "dt": bt["dt"][0], "x0": x0[0], "P0": P0[0],
                    "t_b": float(t_b), "reports": int(rec.measured[sg.steps].sum())})  # fmt: skip
    return out


# -------------------------------------------------------------------------------------------------- FilterPy
def filterpy_imm(ms: ModelSet, seg: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """FilterPy's IMMEstimator on one segment, each step with its own F, Q, R and Π."""
    from filterpy.kalman import IMMEstimator, KalmanFilter

    z, R, dt = seg["z"], seg["R"], seg["dt"]
    filters = []
    for _ in range(ms.r):
        f = KalmanFilter(dim_x=6, dim_z=2)
        f.x, f.P, f.H = seg["x0"].copy(), seg["P0"].copy(), H_POS6
        filters.append(f)
    imm = IMMEstimator(filters, np.asarray(ms.mu0, float), np.asarray(ms.Pi))
    Phi, Qd, Pi = ms.steps(dt)  # every step's models (the whole segment at once, as imm_filter does)
    n = z.shape[0]
    xs, mus = np.empty((n, 6)), np.empty((n, ms.r))
    for k in range(n):
        for j, f in enumerate(filters):
            f.F, f.Q, f.R = Phi[k, j], Qd[k, j], R[k]
        imm.M = Pi[k]
        imm._compute_mixing_probabilities()  # FilterPy mixes with the Π set at its last update: use Π(Δt_k)
        imm.predict()
        if np.isnan(z[k, 0]):  # a missed scan: predict-only, μ = c̄ (the Markov chain alone)
            imm.mu = imm.cbar.copy()
            imm._compute_state_estimate()
        else:
            imm.update(z[k])
        xs[k], mus[k] = imm.x, imm.mu
    return xs, mus


# ------------------------------------------------------------------------------------------------ Stone Soup
def stonesoup_version() -> str:
    try:
        return importlib.metadata.version("stonesoup")
    except importlib.metadata.PackageNotFoundError:
        return ""


def stonesoup_models(cfg: TrackerConfig) -> list[Any]:
    from stonesoup.models.transition.linear import (
        CombinedLinearGaussianTransitionModel,
        ConstantVelocity,
        KnownTurnRate,
    )

    q1, q2, q3 = cfg.imm_q
    w = math.radians(3.0)
    cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(q1), ConstantVelocity(q1)])
    return [cv, KnownTurnRate((q2, q2), w), KnownTurnRate((q3, q3), -w)]


def stonesoup_imm(models: list[Any], ms: ModelSet, seg: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """An IMM of Stone Soup Kalman filters (one predictor and updater per model) on one segment."""
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.predictor.kalman import KalmanPredictor
    from stonesoup.types.detection import Detection
    from stonesoup.types.hypothesis import SingleHypothesis
    from stonesoup.types.state import GaussianState

    z, R, dt = seg["z"], seg["R"], seg["dt"]
    from stonesoup.updater.kalman import KalmanUpdater

    predictors = [KalmanPredictor(m) for m in models]
    updater = KalmanUpdater(None, use_joseph_cov=True)  # Joseph form, as imm_filter and FilterPy
    sel = [0, 1, 2, 3]
    base = datetime(2000, 1, 1)
    t = base + timedelta(seconds=seg["t_b"])
    xs_j = [seg["x0"][sel].copy() for _ in models]
    Ps_j = [seg["P0"][np.ix_(sel, sel)].copy() for _ in models]
    mu = np.asarray(ms.mu0, float)
    _, _, Pis = ms.steps(dt)
    mm = None
    n = z.shape[0]
    xs, mus = np.empty((n, 4)), np.empty((n, len(models)))
    for k in range(n):
        t = t + timedelta(seconds=float(dt[k]))
        Pi = Pis[k]
        cbar = mu @ Pi
        omega = Pi * mu[:, None] / cbar[None, :]  # μ_{i|j}
        X = np.array(xs_j)
        loglik = np.zeros(len(models))
        new_x, new_P = [], []
        measured = not np.isnan(z[k, 0])
        if measured and (mm is None or not np.array_equal(mm.noise_covar, R[k])):
            mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=R[k])
        det = Detection(z[k].reshape(2, 1), timestamp=t, measurement_model=mm) if measured else None
        for j, pred in enumerate(predictors):
            x0j = omega[:, j] @ X
            d = X - x0j
            P0j = sum(omega[i, j] * (Ps_j[i] + np.outer(d[i], d[i])) for i in range(len(models)))
            prior = GaussianState(x0j.reshape(4, 1), P0j, timestamp=t - timedelta(seconds=float(dt[k])))
            p = pred.predict(prior, timestamp=t)
            if measured:
                upd = updater.update(SingleHypothesis(p, det))
                mp = upd.hypothesis.measurement_prediction
                v = np.asarray(det.state_vector - mp.state_vector, float).ravel()
                S = np.asarray(mp.covar, float)
                loglik[j] = -0.5 * (v @ np.linalg.solve(S, v) + np.log(np.linalg.det(2 * np.pi * S)))
                new_x.append(np.asarray(upd.state_vector, float).ravel())
                new_P.append(np.asarray(upd.covar, float))
            else:
                new_x.append(np.asarray(p.state_vector, float).ravel())
                new_P.append(np.asarray(p.covar, float))
        w = np.log(cbar) + loglik
        mu = np.exp(w - w.max())
        mu /= mu.sum()
        xs_j, Ps_j = new_x, new_P
        xs[k], mus[k] = mu @ np.array(new_x), mu
    return xs, mus


# ------------------------------------------------------------------------------------------------------ main
def main() -> int:
    cfg = TrackerConfig.tuned("aircraft")
    t0 = CLOCK()
    tset = read_track_records(DATA)
    t_read = CLOCK() - t0
    rss_read = _maxrss_mb()
    rows_file = tset.rows
    tracks = list(tset.tracks[:N_TRACKS] if N_TRACKS else tset.tracks)
    tset = TrackSet(tuple(tracks), tset.untracked if not N_TRACKS else (), tset.record)
    prep = prepared(tracks, cfg)
    reports = prep["reports"]
    ms = cfg.models(1.0)
    cons = cfg.consistency()

    # 1. this project, the whole collection (in-process, one core)
    t_e2e = {m: best_of(lambda m=m: track_records(tset, (m,), cfg), REPEATS, CLOCK) for m in ("imm", "glr")}
    rss_track = _maxrss_mb()
    t_filt = {
        "imm": best_of(lambda: filter_only(prep, "imm", cfg, cons), REPEATS, CLOCK),
        "imm-nochecks": best_of(lambda: filter_only(prep, "imm", cfg, None), REPEATS, CLOCK),
        "glr": best_of(lambda: filter_only(prep, "glr", cfg, cons), REPEATS, CLOCK),
    }

    # 2. one track per call: the command as a fresh process (child CPU time, and wall time)
    one = read_track_records(ONE_TRACK)
    one_reports = prepared(list(one.tracks), cfg)["reports"]
    argv = [sys.executable, "-m", "motionsig_cli", "maneuver", str(ONE_TRACK), "--method", "imm"]
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep),
    }
    subprocess.run(argv, capture_output=True, check=True, env=env)  # warm the file cache and the byte-code
    cli_cpu, cli_wall = [], []
    for _ in range(REPEATS):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        w0 = time.perf_counter()
        subprocess.run(argv, capture_output=True, check=True, env=env)
        cli_wall.append(time.perf_counter() - w0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cli_cpu.append((r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime))
    t_cli = min(cli_cpu)
    t_one = best_of(lambda: track_records(read_track_records(ONE_TRACK), ("imm",), cfg), REPEATS, CLOCK)

    # 3. FilterPy: correctness gate on the slice's longest segment, then the slice timed
    fp_idx = [i for i, sg in enumerate(prep["segs"]) if sg.track < SLICE_FP]
    fp_segs = segment_inputs(prep, tracks, fp_idx)
    fp_reports = sum(s["reports"] for s in fp_segs)
    g = max(fp_segs, key=lambda s: s["z"].shape[0])
    ours = imm_filter(g["z"], H_POS6, g["R"], ms, g["x0"], g["P0"], dt=g["dt"], consistency=None)
    ref_x, ref_mu = filterpy_imm(ms, g)
    scale = np.maximum(np.abs(ref_x).max(axis=0), 1.0)
    rel = float(np.max(np.abs(ours.x - ref_x) / scale))
    dmu = float(np.max(np.abs(ours.mu - ref_mu)))
    n_gate = g["z"].shape[0]
    ok = gate(
        f"correctness gate (FilterPy): 1 segment of {n_gate} steps ({g['reports']} reports): max relative "
        f"difference of the combined estimate {rel:.2e}, model probabilities {dmu:.2e} (absolute)",
        rel > 1e-8 or dmu > 1e-8, "FAILED: FilterPy and imm_filter differ by more than 1e-8",
    )  # fmt: skip
    if not ok:
        return 1
    t_fp = best_of(lambda: [filterpy_imm(ms, s) for s in fp_segs], REPEATS, CLOCK)
    us_fp = 1e6 * t_fp / fp_reports

    # 4. Stone Soup (optional)
    ss_ver = stonesoup_version()
    ss: dict[str, Any] | None = None
    if ss_ver:
        models = stonesoup_models(cfg)
        sx, smu = stonesoup_imm(models, ms, g)
        sel = [0, 1, 2, 3]
        rel_ss = float(np.max(np.abs(ours.x[:, sel] - sx) / scale[sel]))
        dmu_ss = float(np.max(np.abs(ours.mu - smu)))
        ok = gate(
            f"Stone Soup vs imm_filter on the same segment: position/velocity {rel_ss:.2e} relative, model "
            f"probabilities {dmu_ss:.2e} (absolute)",
            rel_ss > 1e-8 or dmu_ss > 1e-8, "FAILED: the Stone Soup IMM differs from imm_filter by more than 1e-8",
        )  # fmt: skip
        if not ok:
            return 1
        ss_idx = [i for i, sg in enumerate(prep["segs"]) if sg.track < SLICE_SS]
        ss_segs = segment_inputs(prep, tracks, ss_idx)
        ss_reports = sum(s["reports"] for s in ss_segs)
        reps = max(1, min(REPEATS, 2))
        t_ss = best_of(lambda: [stonesoup_imm(models, ms, s) for s in ss_segs], reps, CLOCK)
        ss = {
            "t": t_ss,
            "reports": ss_reports,
            "rel": rel_ss,
            "dmu": dmu_ss,
            "reps": reps,
            "segs": len(ss_segs),
        }
    else:
        print("Stone Soup is not installed (pip install stonesoup): skipped")

    # rows
    def row(case: str, seconds: float, units: int, how: str) -> dict[str, Any]:
        us = 1e6 * seconds / units
        return {"case": case, "seconds": seconds, "units": units, "unit": "report", "us_per_unit": us,
                "ratio_vs_filterpy": us_fp / us, "how": how}  # fmt: skip

    whole = (
        f"whole collection ({len(tracks)} tracks, {len(prep['segs'])} segments), CPU time, best of {REPEATS}"
    )
    rows = [
        {**row("read_track_records (reading, for information)", t_read, reports,
               f"once; {rows_file} rows read, cleaned, projected and laid out; per tracked report"),
         "ratio_vs_filterpy": None},
        row("motionsig IMM filter only", t_filt["imm"], reports, f"{whole}; _run on the batches, tuned checks"),
        row("motionsig IMM filter only, checks off", t_filt["imm-nochecks"], reports,
            f"{whole}; _run on the batches, consistency=None (FilterPy's work)"),
        row("motionsig IMM end to end", t_e2e["imm"], reports, f"{whole}; track_records (batches, filter, table)"),
        row("motionsig GLR filter only", t_filt["glr"], reports, f"{whole}; _run on the batches, tuned checks"),
        row("motionsig GLR end to end", t_e2e["glr"], reports, f"{whole}; track_records (batches, filter, table)"),
        row("motionsig maneuver FILE --method imm (one track per call)", t_cli, one_reports,
            f"{ONE_TRACK.name} as a fresh process, child CPU time, best of {REPEATS} (wall {min(cli_wall):.2f} s); "
            "start-up, reading and the table included"),
        row("motionsig read + IMM, one track in process", t_one, one_reports,
            f"{ONE_TRACK.name}: read_track_records + track_records in this process (the command less its start-up "
            f"and output), CPU time, best of {REPEATS}"),
        {**row("FilterPy IMMEstimator", t_fp * reports / fp_reports, reports, ""), "ratio_vs_filterpy": 1.0,
         "how": f"extrapolated per report from the {len(fp_segs)} segments of the first {SLICE_FP} tracks "
                f"({fp_reports} reports, {t_fp:.2f} s CPU, best of {REPEATS}); one segment at a time"},
    ]  # fmt: skip
    if ss is not None:
        rows.append({**row("Stone Soup IMM (Kalman predictor/updater per model)", ss["t"] * reports / ss["reports"],
                           reports, ""),
                     "how": f"extrapolated per report from the {ss['segs']} segments of the first {SLICE_SS} tracks "
                            f"({ss['reports']} reports, {ss['t']:.2f} s CPU, best of {ss['reps']}); stonesoup "
                            f"{ss_ver}; IMM mixing in NumPy; 4-D state; Joseph update"})  # fmt: skip
    comments = [
        f"workload: {DATA.name}: {rows_file} rows, {len(tracks)} tracks, {len(prep['segs'])} segments, {reports} "
        "tracked reports (measured steps after each segment's two initialising reports); "
        "TrackerConfig.tuned('aircraft'); one thread, process CPU time",
        f"correctness: FilterPy vs imm_filter on 1 segment of {n_gate} steps: combined estimate {rel:.2e} "
        f"(relative), model probabilities {dmu:.2e} (absolute)"
        + (f"; Stone Soup vs imm_filter: position/velocity {ss['rel']:.2e}, model probabilities {ss['dmu']:.2e}"
           if ss is not None else "; Stone Soup not installed"),
        f"peak RSS: {rss_read:.0f} MB after reading, {rss_track:.0f} MB after reading + tracking (IMM and GLR, "
        f"end to end); stonesoup={ss_ver or 'not installed'}",
    ]  # fmt: skip
    write_results("bench_tracks", comments, rows)
    for r in rows:
        print(f"{r['case']:58s} {1e6 / r['us_per_unit']:12,.0f} reports/s/core  {r['us_per_unit']:9.2f} µs/report  "
              + ("" if r["ratio_vs_filterpy"] is None else f"x{r['ratio_vs_filterpy']:.1f} vs FilterPy"))  # fmt: skip
    print(f"peak RSS: {rss_read:.0f} MB after reading, {rss_track:.0f} MB after reading + tracking")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
