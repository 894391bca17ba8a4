"""Test helper: the ADS-B recordings of ``tests/data/adsb/`` as numpy arrays (not package code).

``load_flight("noisy_landing")`` reads ``tests/data/adsb/noisy_landing.csv`` with the stdlib csv
module, in the file's row order (duplicates and stale repeats kept: cleaning them is the tool's job),
and returns float arrays of one length:

- ``t_s``: seconds since the first row's timestamp;
- ``lat``, ``lon``: degrees (WGS-84);
- ``alt_m``: the recorded (barometric) altitude in metres;
- ``gs_mps``: the recorded ground speed in m/s;
- ``track_deg``: the recorded track angle in degrees clockwise from true north;
- ``vrate_mps``: the recorded vertical rate in m/s;
- ``t0_unix_s``: the first row's time in seconds since 1970 (a 0-d array), to align two files.

An empty cell is NaN (the raw message stream has positions and velocities on separate rows). The Cardiff
sample's track column was stored in a signed byte (values in [−128, 127]: the true track modulo 256); it is
repaired here against the course of the recorded positions, and the recorded values are kept as
``track_recorded_deg``.
"""

from __future__ import annotations

import csv
import datetime as dt
from pathlib import Path

import numpy as np

ADSB_DIR = Path(__file__).resolve().parent / "data" / "adsb"
FLIGHTS = (
    "gaps_airbus_tree",
    "raw_rs1090_cdg",
    "noisy_landing",
    "turns_calibration_cardiff",
    "sparse_texas_longhorn",
)
FT = 0.3048
KT = 1852.0 / 3600.0
FPM = FT / 60.0
_COLUMNS = {
    "lat": ("latitude", 1.0),
    "lon": ("longitude", 1.0),
    "alt_m": ("altitude [ft]", FT),
    "gs_mps": ("groundspeed [kt]", KT),
    "track_deg": ("track [deg]", 1.0),
    "vrate_mps": ("vertical_rate [ft/min]", FPM),
}


def _seconds(stamp: str) -> float:
    return dt.datetime.fromisoformat(stamp.replace("Z", "+00:00")).timestamp()


def load_flight(name: str) -> dict[str, np.ndarray]:
    """One recording of ``tests/data/adsb/`` (``name`` without ``.csv``) as arrays; see the module doc."""
    path = ADSB_DIR / f"{name}.csv"
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    t = np.array([_seconds(r["timestamp"]) for r in rows])
    out = {"t_s": t - t[0], "t0_unix_s": np.array(t[0])}
    for key, (column, scale) in _COLUMNS.items():
        out[key] = np.array([float(r[column]) * scale if r.get(column) else np.nan for r in rows])
    if _byte_wrapped(out["track_deg"]):
        out["track_recorded_deg"] = out["track_deg"]
        out["track_deg"] = _unwrap_byte(out)
    return out


def _byte_wrapped(track: np.ndarray) -> bool:
    """A track column stored in a signed byte (values in [−128, 127], some negative): the Cardiff sample's."""
    ok = track[np.isfinite(track)]
    return bool(ok.size and ok.min() >= -128 and ok.max() <= 127 and ok.min() < 0)


def _unwrap_byte(d: dict[str, np.ndarray]) -> np.ndarray:
    """The true track of a byte-wrapped column: v mod 256, or v mod 256 + 256 (a track of 256–359°),
    whichever is nearer the course of the recorded positions (the two are at least 104° apart)."""
    from motionsig_cli.surveillance.local_positions import default_origin

    ok = np.isfinite(d["lat"]) & np.r_[True, np.diff(d["t_s"]) > 0]
    z = default_origin(d["lat"][ok], d["lon"][ok]).to_local(d["lat"][ok], d["lon"][ok])[:, :2]
    v = np.gradient(z, d["t_s"][ok], axis=0)
    course = np.full(d["t_s"].size, np.nan)
    course[ok] = np.degrees(np.arctan2(v[:, 0], v[:, 1])) % 360.0
    course = np.interp(d["t_s"], d["t_s"][ok], np.unwrap(course[ok], period=360.0)) % 360.0

    def off(a: np.ndarray) -> np.ndarray:
        return np.abs((a - course + 180.0) % 360.0 - 180.0)

    c0 = d["track_deg"] % 256.0
    c1 = np.where(c0 < 104.0, c0 + 256.0, np.nan)
    return np.where(np.isfinite(c1) & (off(np.nan_to_num(c1)) < off(c0)), c1, c0)


def load_radar() -> tuple[dict, dict[str, np.ndarray]]:
    """``radar_polar.csv``: its metadata (the ``# key: value`` lines, JSON values) and arrays ``t_s``
    (seconds since the first scan), ``t0_unix_s``, ``range_nm``, ``bearing_deg``, ``altitude_ft``."""
    import json

    meta: dict = {}
    body = []
    with (ADSB_DIR / "radar_polar.csv").open(newline="") as fh:
        for line in fh:
            if line.startswith("#"):
                key, _, value = line[1:].partition(":")
                meta[key.strip()] = json.loads(value)
            else:
                body.append(line)
    rows = list(csv.DictReader(body))
    t = np.array([_seconds(r["time"]) for r in rows])
    out = {"t_s": t - t[0], "t0_unix_s": np.array(t[0])}
    for column in ("range_nm", "bearing_deg", "altitude_ft"):
        out[column] = np.array([float(r[column]) for r in rows])
    return meta, out
