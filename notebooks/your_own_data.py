# %% [markdown]
# # Your own data
#
# The other pages reproduce the source documents on data the tool simulates. This page does what a
# radar, tracking or multilateration engineer does first: bring a file written by *their own* code and
# run the commands on it. Every record below is written here with NumPy and the `csv` module — not by
# `motionsig` — with the habits of real exports: their own column names, units in the header, ISO 8601
# time stamps with jitter, missed scans and empty cells. The commands are run exactly as on a terminal,
# and their output is shown. The record format itself is described on the "Data formats" page.

# %%
# fold: Setup: imports and helper functions
import csv
import json
import subprocess
import sys
import tempfile
from datetime import UTC, datetime, timedelta
from pathlib import Path

import numpy as np
from IPython.display import Image, Markdown, display

WORK = Path(tempfile.mkdtemp(prefix="motionsig-own-data-"))


def motionsig(*args, stdin=None):
    """Run ``motionsig ARGS`` in the work directory as a user would; print its stderr, return its stdout."""
    p = subprocess.run(
        [sys.executable, "-m", "motionsig_cli", *map(str, args)],
        input=stdin, capture_output=True, text=True, cwd=WORK, check=False,
    )  # fmt: skip
    if p.stderr.strip():
        print(p.stderr.strip())
    if p.returncode != 0:
        raise RuntimeError(f"motionsig {' '.join(map(str, args))} exited with {p.returncode}")
    return p.stdout


def rows(text):
    """The CSV body of a command's output (its '# key: value' lines left out), as dicts."""
    return list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))


def meta(text):
    """The '# key: value' metadata of a command's CSV output."""
    out = {}
    for line in text.splitlines():
        if line.startswith("# "):
            key, _, value = line[2:].partition(": ")
            out[key] = json.loads(value)
    return out


def md_table(header, body):
    """A Markdown table from a header and rows of formatted cells."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in body]
    return Markdown("\n".join(lines))


def iso(t0, seconds):
    """ISO 8601 time stamps (UTC, millisecond resolution) ``seconds`` after ``t0``."""
    return [(t0 + timedelta(seconds=float(s))).isoformat(timespec="milliseconds") for s in seconds]


T0 = datetime(2026, 5, 1, 12, 0, 0, tzinfo=UTC)
rng = np.random.default_rng(20260501)

# %% [markdown]
# ## 1. Does this vehicle carry a mode signature? `detect` on a position log
#
# A vehicle under closed-loop control adds a small Gold-code signature to its reference, which names its
# mode (the mode-signature paper, 47th IEEE CDC, Cancún, 2008, eqs 1–3
# and 53–55). Here the vehicle is written from those equations with NumPy: T = 0.1 s, 10 samples per chip,
# feedback gains K = (40, 10), carrier 0.5 Hz, measurement variance 10⁻³ m², mode 2 at a code phase of
# 70 samples — all of it *our* choice, none of it in the file. The file is what a position logger writes:
# ISO time stamps and the position in kilometres, with 5 % of the samples blank or absent. The codes of
# the modes are Table I's, which `motionsig encode table1` writes.

# %%
codes = rows(motionsig("encode", "table1", "--chips", "bipolar"))
chips = np.array(
    [[int(r["value"]) for r in codes if r["code"] == c] for c in dict.fromkeys(r["code"] for r in codes)]
)
T, M_RHO, K, F_C, R, A_SIG, MODE, TAU = 0.1, 10, (40.0, 10.0), 0.5, 1e-3, 0.5, 2, 70


def vehicle(n, signature, seed):
    """Positions of the 1-D closed loop (eqs 53–55) with or without the signature of eqs 1–3."""
    g = np.random.default_rng(seed)
    t = np.arange(n) * T
    p = chips[MODE - 1][((np.arange(n) - TAU) // M_RHO) % chips.shape[1]] * signature
    w = 2 * np.pi * F_C
    z, zd = p * np.cos(w * t + 0.3), -w * p * np.sin(w * t + 0.3)
    wr = 2 * np.pi * 0.01
    r, rd = 10 * np.sin(wr * t), wr * 10 * np.cos(wr * t)
    x, v, y = 0.0, 0.0, np.empty(n)
    for i in range(n):
        y[i] = x + np.sqrt(R) * g.standard_normal()
        u = K[0] * (-x + r[i] + A_SIG * z[i]) + K[1] * (-v + rd[i] + A_SIG * zd[i])
        acc = 0.01 * g.standard_normal()
        x, v = x + T * v + 0.5 * T**2 * acc, v + T * u + T * acc
    return t, y


def write_log(path, t, y):
    """ISO time stamps and kilometres; 5 % of the samples blank (2.5 %) or absent (2.5 %)."""
    g = np.random.default_rng(7)
    drop = g.random(t.size)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["timestamp", "pos [km]"])
        for s, stamp, v in zip(drop, iso(T0, t), y, strict=True):
            if s >= 0.05:
                w.writerow([stamp, f"{v / 1e3:.9f}"])
            elif s < 0.025:
                w.writerow([stamp, ""])


write_log(WORK / "vehicle.csv", *vehicle(400, 1.0, 1))
write_log(WORK / "quiet.csv", *vehicle(400, 0.0, 2))
print((WORK / "vehicle.csv").read_text()[:200])

# %% [markdown]
# The record holds no model: the filters' model is given with `simulate`'s option names (the sample period
# comes from the time stamps, the codes are Table I's by default). `--pfa 0.1` asks the question the argmax
# alone cannot answer — is there a signature at all? — with a threshold per horizon calibrated on null
# records simulated from the same model, with the same missing samples.

# %%
model = ["--columns", "y=pos", "--mrho", M_RHO, "--K", "40,10", "--R", R, "--fc", F_C, "--horizons", "20,40",
         "--pfa", "0.1"]  # fmt: skip
verdicts = []
for name in ("vehicle.csv", "quiet.csv"):
    out = motionsig("detect", name, *model)
    for r in rows(out):
        verdicts.append((name, r["horizon_s"], r["mode_hat"], r["tau_hat"], f"{float(r['statistic']):.3g}",
                         f"{float(r['threshold']):.3g}", r["signature_present"]))  # fmt: skip
m = meta(out)
print("model sources:", m["model_sources"])
display(md_table(["file", "horizon [s]", "mode", "τ [samples]", "max Λ", "threshold", "signature"], verdicts))

# %% [markdown]
# Check: on the vehicle's log the detector names mode 2 at code phase 70 and declares a signature; on the
# quiet vehicle (the same loop without a signature) the argmax still names *a* mode — which is why a
# threshold is needed — and no signature is declared at 40 s. (At P_FA = 0.1 a false declaration on the
# quiet record has probability 0.1 per horizon; the seeds are fixed.)

# %%
assert all(v[2:4] == ("2", "70") and v[6] == "true" for v in verdicts if v[0] == "vehicle.csv")
assert [v[6] for v in verdicts if v[0] == "quiet.csv"][-1] == "false"

# %% [markdown]
# ## 2. A manoeuvring target: `maneuver FILE`
#
# A radar's track export: one row per scan with a time stamp, east and north positions in kilometres, and
# a blank where the plot was missed. The target flies at 150 m/s for 200 s and then accelerates at 20 m/s²
# across its track for 10 s; the scan period is 1 s with a few milliseconds of time-stamp jitter, about
# 10 % of the scans are missed, and the position error is 50 m per axis. None of this is in the file
# except the numbers: the trackers take the period from the time stamps and, as no σ is given, estimate
# it from the data (second differences, robust to the manoeuvre; the metadata says how).

# %%
N_SCANS, ONSET, SIGMA = 360, 200, 50.0
k = np.arange(N_SCANS)
accel = np.where((k >= ONSET) & (k < ONSET + 10), 20.0, 0.0)  # m/s² on the north axis
vel = np.stack([np.full(N_SCANS, 150.0), np.r_[0.0, np.cumsum(accel[:-1])]], axis=-1)
pos = np.r_[[[0.0, 0.0]], np.cumsum(vel[:-1] + 0.5 * np.c_[np.zeros(N_SCANS - 1), accel[:-1]], axis=0)]
meas = pos + SIGMA * rng.standard_normal(pos.shape)
missed = rng.random(N_SCANS) < 0.10
missed[:3] = False  # the trackers start from two measured scans
stamps = iso(T0, k + rng.uniform(-0.004, 0.004, N_SCANS))

with open(WORK / "track.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["Timestamp", "East [km]", "North [km]"])
    for i in range(N_SCANS):
        if missed[i] and i % 2:  # half of the missed scans are blank cells, half are absent rows
            w.writerow([stamps[i], "", ""])
        elif not missed[i]:
            w.writerow([stamps[i], f"{meas[i, 0] / 1e3:.4f}", f"{meas[i, 1] / 1e3:.4f}"])
print((WORK / "track.csv").read_text()[:260])

# %% [markdown]
# `East` and `North` are not names the command knows, so they are mapped with `--columns`; the unit comes
# from the header. All four trackers run on the same record. The MLR threshold is set to 5 (the paper's 0
# declares at most scans of a straight flight, because the MLR statistic's H0 mean is not zero; assumed).

# %%
# alt: Four panels for track.csv: the measured positions and the IMM, GLR, MLR and CV tracks in the x-y plane in km (a straight leg, then a turn near x = 31 km) with the declarations marked; the estimated speed against the scan; each method's declarations and the missed scans; the IMM's model probabilities.
out = motionsig("maneuver", "--input", "track.csv", "--columns", "time=Timestamp,x=East,y=North",
                "--method", "all", "--mlr-threshold", "5", "--plot", "track.png")  # fmt: skip
m = meta(out)
print(
    {key: m[key] for key in m if key in ("T", "T_source", "sigma", "sigma_source", "scans", "missed_scans")}
)
declared, early = {}, {}
for r in rows(out):
    if r["declared"] != "true":
        continue
    if int(r["scan"]) <= ONSET + 1:  # before the manoeuvre: a false alarm
        early[r["method"]] = early.get(r["method"], 0) + 1
    elif r["method"] not in declared:
        declared[r["method"]] = (int(r["scan"]), int(r["onset"]))
display(md_table(
    ["method", "false alarms before the onset", "first declaration after it, at scan", "estimated onset",
     "true onset"],
    [(name, early.get(name, 0), scan, onset, ONSET + 1) for name, (scan, onset) in declared.items()],
))  # fmt: skip
display(Image(filename=WORK / "track.png"))

# %% [markdown]
# Check: the GLR and MLR detectors estimate the onset of the acceleration within their window (10 scans) of
# the true one (the scan numbers of the output count from 1), and σ is recovered within three standard
# errors: the MAD estimate from about 2 × 320 second differences has a standard error of about 5.6 %
# (measured on 200 simulated records like this one; a Gaussian MAD's efficiency is 37 %).

# %%
for name in ("glr", "mlr"):
    scan, onset = declared[name]
    assert abs(onset - (ONSET + 1)) <= 10, (name, onset)
assert abs(m["sigma"] / SIGMA - 1) < 3 * 0.056, m["sigma"]

# %% [markdown]
# ## 3. Is there a target? `slrt FILE` on three radars' detections
#
# Three radars report detections (range in metres, bearing in degrees, counter-clockwise from east), with
# clutter, each with its own noise, detection probability and false-alarm rate. The sensors file says so;
# the detections file has one row per detection with an ISO time stamp. The track starts from `--init`
# (one scan before the first); Wald's test with α = 10⁻³, β = 0.1 decides.

# %%
SENSORS = [  # id, x, y [m], sigma_r [m], sigma_phi [deg], p_D, clutter per scan, field of view [m]
    ("north", 0.0, 12_000.0, 40.0, 0.3, 0.9, 4.0, 25_000.0),
    ("west", -11_000.0, -4_000.0, 60.0, 0.2, 0.8, 6.0, 25_000.0),
    ("east", 10_000.0, -6_000.0, 50.0, 0.25, 0.85, 5.0, 25_000.0),
]
with open(WORK / "sensors.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["sensor", "x [m]", "y [m]", "sigma_r [m]", "sigma_phi [deg]", "pd", "clutter", "fov [m]"])
    w.writerows(SENSORS)


def detections(path, target):
    """30 scans of detections of the three radars, with or without a target at 140 m/s."""
    x0 = np.array([-1_000.0, 140.0, 500.0, -20.0])  # x, vx, y, vy
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "radar", "range [m]", "bearing [deg]"])
        for scan in range(1, 31):
            t = x0[[0, 2]] + scan * x0[[1, 3]]
            stamp = iso(T0, [scan])[0]
            for sid, sx, sy, s_r, s_phi, pd, clutter, fov in SENSORS:
                dets = []
                if target and rng.random() < pd:
                    d = t - (sx, sy)
                    dets.append((np.hypot(*d) + s_r * rng.standard_normal(),
                                 np.degrees(np.arctan2(d[1], d[0])) + s_phi * rng.standard_normal()))  # fmt: skip
                for _ in range(rng.poisson(clutter)):
                    dets.append((fov * rng.random(), rng.uniform(-180.0, 180.0)))
                for r, b in dets:
                    w.writerow([stamp, sid, f"{r:.2f}", f"{(b + 180) % 360 - 180:.4f}"])


detections(WORK / "target.csv", True)
detections(WORK / "clutter.csv", False)
common = ["--sensor-table", "sensors.csv", "--columns", "sensor=radar", "--init", "-860,140,480,-20",
          "--view", "decisions"]  # fmt: skip
decided = []
for name in ("target.csv", "clutter.csv"):
    for r in rows(motionsig("slrt", "--input", name, *common)):
        decided.append(
            (name, r["method"], r["decision"], r["decision_scan"], f"{float(r['last_log_lr']):.1f}")
        )
display(md_table(["file", "method", "decision", "at scan", "log LR at scan 30"], decided))

# %% [markdown]
# Check: every method confirms the target, and none confirms a track in the clutter-only file (Wald's
# α = 10⁻³ makes a false confirmation rare; the seed is fixed).

# %%
assert all(d[2] == "confirmed" for d in decided if d[0] == "target.csv")
assert all(d[2] != "confirmed" for d in decided if d[0] == "clutter.csv")

# %% [markdown]
# ## 4. Where is the transmitter? `track-sat solve` on a multilateration network
#
# ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972) locates an aircraft from the times
# at which its pulses reach several receivers, and tracks its transmitter's clock across epochs (§4.5).
# The same estimators run on a wide-area multilateration network: six ground stations within 15 km of an
# airport, given by WGS-84 latitude, longitude and altitude; an aircraft climbing through 2–4 km; a
# transmitter clock that drifts (a random walk with a random rate, σ0 = 20 ns per epoch); time-of-arrival
# errors of 10 ns; for 10 s only three stations hear it (the report's outage case). The receivers file
# and the TOA record are written here with NumPy's own WGS-84 conversion.

# %%
A, E2 = 6_378_137.0, 6.69437999014e-3  # WGS-84 semi-major axis [m], first eccentricity squared
C_LIGHT = 299_792_458.0


def wgs84_ecef(lat_deg, lon_deg, alt_m):
    """Geodetic latitude, longitude, altitude → ECEF [m] (the textbook closed form)."""
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    n = A / np.sqrt(1 - E2 * np.sin(lat) ** 2)
    return np.stack([(n + alt_m) * np.cos(lat) * np.cos(lon), (n + alt_m) * np.cos(lat) * np.sin(lon),
                     (n * (1 - E2) + alt_m) * np.sin(lat)], axis=-1)  # fmt: skip


STATIONS = {  # name: latitude, longitude [deg], altitude [m]
    "MUC": (48.3538, 11.7861, 453.0), "FRS": (48.3720, 11.9890, 480.0), "ERD": (48.4260, 11.6240, 430.0),
    "MOO": (48.2280, 11.8260, 510.0), "NEU": (48.2730, 11.7050, 460.0), "LAN": (48.4610, 11.9050, 440.0),
}  # fmt: skip
with open(WORK / "stations.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["station", "latitude [deg]", "longitude [deg]", "altitude [m]"])
    w.writerows([name, *pos] for name, pos in STATIONS.items())
S = wgs84_ecef(*np.array(list(STATIONS.values())).T)

EPOCHS, SIGMA_NS, SIGMA0_NS = 120, 10.0, 20.0
g = np.random.default_rng(7)
lat = np.linspace(48.20, 48.50, EPOCHS)
lon = np.linspace(11.60, 11.95, EPOCHS)
alt = np.linspace(2_000.0, 4_000.0, EPOCHS)
truth = wgs84_ecef(lat, lon, alt)
s0 = SIGMA0_NS * 1e-9
offset = (
    1e-4
    + np.r_[0.0, np.cumsum(g.standard_normal(EPOCHS - 1) * s0)]
    + np.arange(EPOCHS) * g.standard_normal() * s0
)
t = 1000.0 + np.arange(EPOCHS)
with open(WORK / "toa.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["epoch", "time", "station", "toa", "sigma [ns]"])
    for n in range(EPOCHS):
        for j, name in enumerate(STATIONS):
            if 60 <= n < 70 and j >= 3:
                continue  # three stations only, for 10 s
            toa = (
                t[n]
                + offset[n]
                + np.linalg.norm(truth[n] - S[j]) / C_LIGHT
                + SIGMA_NS * 1e-9 * g.standard_normal()
            )
            w.writerow([n, repr(float(t[n])), name, repr(float(toa)), SIGMA_NS])
print((WORK / "toa.csv").read_text()[:250])

# %% [markdown]
# A snapshot fix needs four receivers (three positions and the clock), so the plain epoch-by-epoch solution
# has no fix in the outage (each such epoch's row says why, and the run goes on); the clock tracker rides
# through it on its clock prediction.

# %%
snap = rows(motionsig("track-sat", "solve", "toa.csv", "--receivers", "stations.csv"))
print(sorted({r["status"] for r in snap}))
out = motionsig("track-sat", "solve", "toa.csv", "--receivers", "stations.csv", "--clock", "track",
                "--sigma0", SIGMA0_NS)  # fmt: skip
fix = rows(out)


def err(prefix):
    """Position error [m] per epoch of the snapshot fix ('') or of the tracker ('track_'); NaN where none."""
    e = np.full(EPOCHS, np.nan)
    for n, r in enumerate(fix):
        if r[f"{prefix}x_m"]:
            e[n] = np.linalg.norm([float(r[f"{prefix}{c}_m"]) for c in "xyz"] - truth[n])
    return e


def clock_err(prefix):
    return np.array([float(r[f"{prefix}clock_offset_s"]) if r[f"{prefix}clock_offset_s"] else np.nan
                     for r in fix]) - offset  # fmt: skip


outage = slice(60, 70)
display(md_table(
    ["estimate", "RMS position error [m], all epochs", "in the outage", "RMS clock error [ns]"],
    [("snapshot fix (≥ 4 stations)", f"{np.sqrt(np.nanmean(err('') ** 2)):.1f}", "—",
      f"{1e9 * np.sqrt(np.nanmean(clock_err('') ** 2)):.1f}"),
     ("clock tracking (§4.5)", f"{np.sqrt(np.nanmean(err('track_') ** 2)):.1f}",
      f"{np.sqrt(np.nanmean(err('track_')[outage] ** 2)):.1f}",
      f"{1e9 * np.sqrt(np.nanmean(clock_err('track_') ** 2)):.1f}")],
))  # fmt: skip

# %% [markdown]
# Check: the snapshot fix has no estimate in the outage, the tracker has one at every epoch, and the
# tracker's clock error is smaller than the snapshot's (it averages the clock over epochs).

# %%
assert np.all(np.isnan(err("")[outage])) and not np.any(np.isnan(err("track_")))
assert [r["status"] for r in snap[outage]] == ["no fix: 3 receiver(s), a fix needs 4"] * 10
assert np.nanmean(clock_err("track_") ** 2) < np.nanmean(clock_err("") ** 2)

# %% [markdown]
# ## 5. JSON between commands
#
# Every command writes JSON with `-f json`, and every reading command reads it: the metadata travel with
# the data. Here a simulated run's detections go from one `slrt` to the next as JSON.

# %%
dets_json = motionsig("slrt", "--view", "detections", "--runs", "1", "-f", "json")
sensors_csv = motionsig("slrt", "--view", "sensors", "--runs", "1")
(WORK / "sim_sensors.csv").write_text(sensors_csv)
out = motionsig(
    "slrt", "--input", "-", "--sensor-table", "sim_sensors.csv", "--view", "decisions", stdin=dets_json
)
print("\n".join(line for line in out.splitlines() if not line.startswith("#")))
