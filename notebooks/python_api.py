# %% [markdown]
# # The systems from Python
#
# Every command of `motionsig` is a thin layer over the package `motionsig_cli`, and each system has a
# public entry point that takes plain arrays (the page "Python API" documents them):
#
# | system | function | command |
# |---|---|---|
# | manoeuvre trackers (IMM, GLR, MLR, CV) | `track_positions` | `motionsig maneuver --input` |
# | LMP mode detector | `detect_mode`, `detect_mode_radar` | `motionsig detect RECORD` |
# | multilateration | `solve_epoch` | `motionsig track-sat solve` |
# | track existence (SLRT) | `score_detections` | `motionsig slrt --input` |
#
# Each runs here on one record made in this notebook, and a numerical check follows each result. The whole
# page runs in seconds.

# %%
import math

import numpy as np

from motionsig_cli import (
    Sensor,
    SlrtRecordConfig,
    TrackerConfig,
    Vehicle1D,
    detect_mode,
    score_detections,
    solve_epoch,
    track_positions,
)
from motionsig_cli.geodesy import enu_to_ecef
from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record

# %% [markdown]
# ## A tracker on one track
#
# A target flies east at 300 m/s and from t = 30 s accelerates north at 3 m/s²; its positions are measured
# every second with σ = 50 m per axis, and scan 10 is missed. `track_positions` takes the times, the (N, 2)
# positions and σ; the GLR tracker declares the manoeuvre and estimates its onset and its acceleration.

# %%
rng = np.random.default_rng(1)
t = np.arange(60.0)
truth = np.stack([300.0 * t, 1.5 * np.maximum(t - 30.0, 0.0) ** 2], axis=1)
z = truth + 50.0 * rng.standard_normal(truth.shape)
z[10] = np.nan
glr = track_positions(t, z, 50.0, method="glr", config=TrackerConfig())
first = int(np.flatnonzero(glr.detected)[0])
onset_t = float(glr.t[glr.onset[first]])
print(
    f"declared at t = {glr.t[first]:g} s, onset t = {onset_t:g} s, input jump {glr.u_jump[first].round(2)} m/s²"
)
err = glr.position - truth[glr.row]
rms = float(np.sqrt(np.mean(np.sum(err[glr.measured] ** 2, axis=1))))
print(f"position RMS error {rms:.1f} m over {glr.measured.sum()} measured scans")

# %%
assert abs(onset_t - 30.0) <= 5.0  # the onset within 5 scans of the truth
assert abs(glr.u_jump[first][1] - 3.0) < 2.5 and abs(glr.u_jump[first][0]) < 2.5  # about (0, 3) m/s²
assert rms < 50.0  # filtering beats the raw measurements (σ√2 = 71 m per position)
imm = track_positions(t, z, 50.0, method="imm")
assert np.allclose(imm.mu.sum(axis=-1), 1.0) and imm.mu[-1, 1:].sum() > 0.5  # the CA models at the end

# %% [markdown]
# ## The LMP detector on one record
#
# A 1-D record of 20 s carries the signature of mode 2 at code phase 5 chips (simulated as `motionsig
# simulate` does). `detect_mode` takes its times and positions; the model the filters assume is `simulate`'s
# default, and could be given by name (`T=…`, `m_rho=…`, `R=…`).

# %%
sim = simulate_record(RecordConfig(Vehicle1D(), mode=2, tau_chips=5, duration=20.0, seed=1))
det = detect_mode(sim.t, sim.y, horizons=[10.0, 20.0])
print(det.summary)

# %%
assert det.mode[-1] == 2 and det.tau_chips[-1] == 5.0  # the truth at the 20 s horizon
assert det.margin[-1] > 0 and det.statistic[-1] == det.result.Lambda[:, 0, -1].max()

# %% [markdown]
# ## One multilateration epoch
#
# Five receivers about 20 km apart see a pulse emitted at t = 12.5 s by a transmitter 5 km up; the times of
# arrival carry 3 ns of noise. `solve_epoch` returns the position, the emission time and their covariance.

# %%
enu = np.array(
    [[-1e4, -8e3, 0], [1.2e4, -1e4, 50], [9e3, 1.1e4, -30], [-7e3, 9e3, 100], [0, 1.5e4, 20]], float
)
S = enu_to_ecef(enu, 45.0, 0.0, 0.0)
p = enu_to_ecef(np.array([1000.0, 2000.0, 5000.0]), 45.0, 0.0, 0.0)
toa = 12.5 + np.linalg.norm(S - p, axis=1) / 299_792_458.0 + 3e-9 * rng.standard_normal(5)
fix = solve_epoch(S, toa, sigma=3e-9)
miss = float(np.linalg.norm(fix.position - p))
print(
    f"height {fix.alt_m:.1f} m, miss {miss:.2f} m, sd (E, N, U) {fix.sd_enu.round(2)} m, PDOP {fix.pdop:.2f}"
)

# %%
sd3 = float(np.sqrt(np.trace(fix.covariance[:3, :3])))
assert fix.converged and miss < 5 * sd3  # within five standard deviations of the truth
assert abs(fix.emission_time - 12.5) < 1e-7

# %% [markdown]
# ## One SLRT run
#
# Two radars look at a target crossing at 200 m/s; each detects it with probability 0.9 and reports one
# false alarm per scan on average, uniform in its field of view. `score_detections` runs every fusion rule
# of `motionsig slrt` on the detections and Wald's test confirms the track.

# %%
radars = [
    Sensor(f"r{i + 1}", x, y, pd=0.9, fov=30e3, clutter=1.0, sigma_r=20.0, sigma_phi=math.radians(0.5))
    for i, (x, y) in enumerate([(0.0, 0.0), (15e3, -5e3)])
]
rows = []
for k in range(1, 16):
    target = np.array([2000.0 + 200.0 * k, 8000.0])
    for s in radars:
        d = target - (s.x, s.y)
        if rng.random() < 0.9:
            rows.append((float(k), s.label, np.hypot(*d) + 20.0 * rng.standard_normal(),
                         math.atan2(d[1], d[0]) + math.radians(0.5) * rng.standard_normal()))  # fmt: skip
        for _ in range(rng.poisson(1.0)):
            rows.append((float(k), s.label, 30e3 * rng.random(), math.pi * (2 * rng.random() - 1)))
        rows.append((float(k), s.label, math.nan, math.nan))  # the scan, even without detections
times = np.array([r[0] for r in rows])
labels = [r[1] for r in rows]
meas = np.array([r[2:] for r in rows])
cfg = SlrtRecordConfig(init=(2000.0, 200.0, 8000.0, 0.0), init_sd=(200.0, 50.0))
scores = score_detections(times, labels, meas, radars, config=cfg)
for m in scores.methods:
    print(f"{m:>14}: log LR {scores.final(m)[0]:8.2f}, decision {int(scores.decision[m][0]):+d}")

# %%
log_a, log_b = scores.thresholds
assert scores.decision["ckf"][0] == 1 and scores.final("ckf")[0] > log_b  # confirmed
assert scores.decision_time["ckf"][0] <= 15.0
