"""Write the ADS-B test recordings of ``tests/data/adsb/`` from the sample flights of the traffic wheel.

Usage::

    pip download --no-deps traffic==2.13 -d /tmp/traffic
    cd /tmp/traffic && unzip -o -q traffic-2.13-py3-none-any.whl
    python scripts/make_adsb_samples.py /tmp/traffic [--out tests/data/adsb]

The argument is the folder the wheel was extracted into (the one holding ``traffic/data/samples``).
The script is deterministic: the same wheel gives the same bytes (the radar export's noise comes from
``numpy.random.default_rng(RADAR_SEED)``). It prints the statistics table of ``tests/data/adsb/README.md``.

Each recording is written *as recorded*: rows in the recording's order, duplicates and repeated
(stale) positions kept, values as the sample holds them (floats in their shortest round-trip form),
an absent value as an empty cell. Nothing is cleaned, resampled or sorted.
"""

from __future__ import annotations

import argparse
import csv
import datetime as dt
import gzip
import io
import json
import sys
from pathlib import Path

import numpy as np

COLUMNS = (
    "timestamp",
    "icao24",
    "callsign",
    "latitude",
    "longitude",
    "altitude [ft]",
    "groundspeed [kt]",
    "track [deg]",
    "vertical_rate [ft/min]",
)
SOURCE_KEYS = (
    "icao24",
    "callsign",
    "latitude",
    "longitude",
    "altitude",
    "groundspeed",
    "track",
    "vertical_rate",
)

# name -> (sample path inside the wheel, window (start, end) in seconds from the first row or None)
FLIGHTS: dict[str, tuple[str, tuple[float, float] | None]] = {
    # a long flight with coverage gaps of several minutes: the 2 h window holding the most gap time
    "gaps_airbus_tree": ("featured/airbus_tree.json.gz", None),  # window chosen below
    # raw decoded messages (rs1090), ~0.5 s irregular, the same frame received twice: the first 40 min
    "raw_rs1090_cdg": ("rs1090/full_flight_short.jsonl", (0.0, 2400.0)),
    # an approach and landing at Zurich whose positions often repeat the previous one (OpenSky, 1 s)
    "noisy_landing": ("noisy/noisy_landing.json.gz", None),
    # a navaid calibration flight around Cardiff: many turns
    "turns_calibration_cardiff": ("calibration/cardiff.json.gz", None),
    # sparse reports: most seconds without a report (median 6 s, gaps of minutes)
    "sparse_texas_longhorn": ("featured/texas_longhorn.json.gz", None),
}
MAX_WINDOW_S = 7200.0
GAP_S = 30.0

# the simulated radar of radar_polar.csv (a hypothetical site in Somerset, ~35 NM from the flight)
RADAR_FLIGHT = "turns_calibration_cardiff"
RADAR_SITE = {"latitude": 51.06, "longitude": -2.60, "altitude_m": 100.0}
RADAR_SEED = 20260512
RADAR_PERIOD_S = 4.0
RADAR_JITTER_S = 0.3
RADAR_P_MISS = 0.10
SIGMA_RANGE_NM = 0.03
SIGMA_BEARING_DEG = 0.08
NM = 1852.0
FT = 0.3048


def _fmt(v: object) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        if v != v:  # NaN
            return ""
        return repr(v)
    return str(v)


def _iso(t_ms: int) -> str:
    t = dt.datetime.fromtimestamp(t_ms / 1000, tz=dt.UTC)
    return t.strftime("%Y-%m-%dT%H:%M:%S.") + f"{t_ms % 1000:03d}Z"


def _records(path: Path) -> list[dict]:
    """A sample's rows as dicts with an integer millisecond ``timestamp``, in the file's order."""
    if path.suffix == ".jsonl":
        rows = []
        for line in path.read_text().splitlines():
            r = json.loads(line)
            bds = r.get("bds")
            # the messages that carry a column of ours: positions (BDS 0,5 airborne; 0,6 surface),
            # velocity (BDS 0,9) and identification (BDS 0,8), each a row of its own
            if r.get("df") in ("17", "18") and bds in ("05", "06", "08", "09"):
                r["timestamp"] = round(r["timestamp"] * 1000)
                if bds == "06":
                    r.pop("altitude", None)
                if bds != "09":
                    r.pop("vertical_rate", None)
                rows.append(r)
        return rows
    data = json.loads(gzip.open(path).read())
    if isinstance(data, dict):  # pandas' column orientation
        keys = list(data)
        index = list(data[keys[0]])
        data = [{k: data[k][i] for k in keys} for i in index]
    for r in data:
        r["timestamp"] = int(r["timestamp"])
    return data


def _gap_window(rows: list[dict]) -> tuple[float, float]:
    """The contiguous 2 h window (starting at a row) that holds the most time in gaps > 30 s."""
    t = np.array([r["timestamp"] for r in rows]) / 1000.0
    t = t - t[0]
    gaps = np.diff(t)
    best, best_start = -1.0, 0.0
    for start in t:
        inside = (t[:-1] >= start) & (t[1:] <= start + MAX_WINDOW_S) & (gaps > GAP_S)
        total = float(gaps[inside].sum())
        if total > best + 1e-9:
            best, best_start = total, float(start)
    return best_start, best_start + MAX_WINDOW_S


def _rows(samples: Path, name: str) -> list[dict]:
    rel, window = FLIGHTS[name]
    rows = _records(samples / rel)
    if name == "gaps_airbus_tree":
        window = _gap_window(rows)
    if window is not None:
        t0 = rows[0]["timestamp"]
        rows = [r for r in rows if window[0] <= (r["timestamp"] - t0) / 1000.0 <= window[1]]
    return rows


def write_flight(rows: list[dict], path: Path) -> None:
    with path.open("w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(COLUMNS)
        for r in rows:
            w.writerow([_iso(r["timestamp"])] + [_fmt(r.get(k)) for k in SOURCE_KEYS])


COLLECTION = "collections/quickstart.json.gz"
"""A collection of many flights: traffic's quickstart sample (OpenSky state vectors around Paris, 3 h,
213 aircraft, rows interleaved in time)."""


def write_collection(samples: Path, path: Path) -> tuple[int, int]:
    """The collection as recorded, gzip-compressed CSV (deterministic: no name or time in the gzip header),
    rows in the sample's order; returns (rows, aircraft)."""
    rows = _records(samples / COLLECTION)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for r in rows:
        w.writerow([_iso(r["timestamp"])] + [_fmt(r.get(k)) for k in SOURCE_KEYS])
    with path.open("wb") as raw, gzip.GzipFile(filename="", mode="wb", fileobj=raw, mtime=0, compresslevel=9) as gz:
        gz.write(buf.getvalue().encode())
    return len(rows), len({r["icao24"] for r in rows})


def stats(rows: list[dict]) -> dict:
    """The README's statistics. For the raw message stream, Δt, stale repeats and gaps are over the
    position rows (the rows with a latitude); duplicates are over every row."""
    lines = [tuple([r["timestamp"]] + [_fmt(r.get(k)) for k in SOURCE_KEYS]) for r in rows]
    seen: set = set()
    dups = 0
    for line in lines:
        dups += line in seen
        seen.add(line)
    pos = [r for r in rows if r.get("latitude") is not None]
    t = np.array([r["timestamp"] for r in pos]) / 1000.0
    d = np.diff(t)
    lat = np.array([r["latitude"] for r in pos], float)
    lon = np.array([r["longitude"] for r in pos], float)
    stale = int(np.sum((d > 0) & (lat[1:] == lat[:-1]) & (lon[1:] == lon[:-1])))
    t_all = np.array([r["timestamp"] for r in rows]) / 1000.0
    span = t_all[-1] - t_all[0]
    seconds = len(set(np.floor(t_all).astype(int)))
    return {
        "icao24": rows[0]["icao24"],
        "callsign": next((r["callsign"] for r in rows if r.get("callsign")), ""),
        "start": _iso(rows[0]["timestamp"]),
        "duration_min": span / 60.0,
        "rows": len(rows),
        "position_rows": len(pos),
        "dt_p5": float(np.percentile(d, 5)),
        "dt_median": float(np.median(d)),
        "dt_p95": float(np.percentile(d, 95)),
        "dt_max": float(d.max()),
        "duplicates": dups,
        "stale": stale,
        "gaps_30s": int(np.sum(d > GAP_S)),
        "gap_time_min": float(d[d > GAP_S].sum() / 60.0),
        "seconds_with_report": seconds / (np.floor(span) + 1),
    }


def _ecef(lat_deg: np.ndarray, lon_deg: np.ndarray, h_m: np.ndarray) -> np.ndarray:
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    return np.stack(
        [
            (n + h_m) * np.cos(lat) * np.cos(lon),
            (n + h_m) * np.cos(lat) * np.sin(lon),
            (n * (1 - e2) + h_m) * np.sin(lat),
        ],
        axis=-1,
    )


def write_radar(rows: list[dict], path: Path) -> int:
    """A 4 s radar's track export of the flight: positions interpolated linearly in ECEF at the scan
    times (altitude taken as height above the ellipsoid), slant range and azimuth from the site
    (pymap3d's ``ecef2aer``), noise added; missed scans dropped, and scans beyond the radar horizon
    of a 4/3-earth atmosphere (ground range > 1.23 (sqrt(h_site) + sqrt(h_aircraft)) NM, heights in
    ft) or of an aircraft at altitude <= 0 ft (on the ground) dropped. ``altitude_ft`` is Mode C: the last recorded altitude at or before the scan, to the
    nearest 100 ft."""
    import pymap3d

    t_ms = np.array([r["timestamp"] for r in rows], dtype=np.int64)
    t = (t_ms - t_ms[0]) / 1000.0
    xyz = _ecef(
        np.array([r["latitude"] for r in rows], float),
        np.array([r["longitude"] for r in rows], float),
        np.array([r["altitude"] for r in rows], float) * FT,
    )
    alt_ft = np.array([r["altitude"] for r in rows], float)
    rng = np.random.default_rng(RADAR_SEED)
    n_scan = int(np.floor(t[-1] / RADAR_PERIOD_S))
    ts = np.arange(1, n_scan) * RADAR_PERIOD_S + rng.uniform(-RADAR_JITTER_S, RADAR_JITTER_S, n_scan - 1)
    hit = rng.uniform(size=ts.size) >= RADAR_P_MISS
    p = np.stack([np.interp(ts, t, xyz[:, k]) for k in range(3)], axis=-1)
    az, el, srange = pymap3d.ecef2aer(
        p[:, 0], p[:, 1], p[:, 2], RADAR_SITE["latitude"], RADAR_SITE["longitude"], RADAR_SITE["altitude_m"]
    )
    r_nm = srange / NM + rng.normal(0.0, SIGMA_RANGE_NM, ts.size)
    b_deg = np.mod(az + rng.normal(0.0, SIGMA_BEARING_DEG, ts.size), 360.0)
    mode_c = np.round(alt_ft[np.searchsorted(t, ts, side="right") - 1] / 100.0) * 100.0
    alt_now = np.interp(ts, t, alt_ft)
    site_ft = RADAR_SITE["altitude_m"] / FT
    horizon_nm = 1.23 * (np.sqrt(site_ft) + np.sqrt(np.maximum(alt_now, 0.0)))
    keep = hit & (alt_now > 0.0) & (srange * np.cos(np.radians(el)) / NM <= horizon_nm)
    meta = {
        "source": "derived: real ADS-B trajectory (traffic 2.13, calibration/cardiff.json.gz), simulated radar",
        "sensor": RADAR_SITE,
        "scan_period_s": RADAR_PERIOD_S,
        "scan_jitter_s": RADAR_JITTER_S,
        "p_miss": RADAR_P_MISS,
        "sigma_range_nm": SIGMA_RANGE_NM,
        "sigma_bearing_deg": SIGMA_BEARING_DEG,
        "range": "slant range from the site",
        "bearing": "clockwise from true north",
        "visibility": "4/3-earth radar horizon; aircraft above 0 ft",
        "seed": RADAR_SEED,
    }
    with path.open("w", newline="") as fh:
        for k, v in meta.items():
            fh.write(f"# {k}: {json.dumps(v)}\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(("time", "range_nm", "bearing_deg", "altitude_ft"))
        for i in np.flatnonzero(keep):
            w.writerow(
                (
                    _iso(int(t_ms[0] + round(ts[i] * 1000))),
                    f"{r_nm[i]:.4f}",
                    f"{b_deg[i]:.4f}",
                    f"{mode_c[i]:.0f}",
                )
            )
    return int(keep.sum())


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("wheel_dir", type=Path, help="the folder the traffic 2.13 wheel was extracted into")
    ap.add_argument(
        "--out", type=Path, default=Path(__file__).resolve().parents[1] / "tests" / "data" / "adsb"
    )
    args = ap.parse_args(argv)
    samples = args.wheel_dir / "traffic" / "data" / "samples"
    if not samples.is_dir():
        print(f"no traffic/data/samples under {args.wheel_dir}", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    print(
        "| file | aircraft (icao24, callsign) | start (UTC) | duration | rows (positions) | Δt p5 / median / p95 / max [s] "
        "| exact duplicates | stale repeats | gaps > 30 s (total) | seconds with a report |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in FLIGHTS:
        rows = _rows(samples, name)
        path = args.out / f"{name}.csv"
        write_flight(rows, path)
        s = stats(rows)
        print(
            f"| `{name}.csv` | {s['icao24']}, {s['callsign']} | {s['start']} | {s['duration_min']:.1f} min "
            f"| {s['rows']} ({s['position_rows']}) | {s['dt_p5']:.2f} / {s['dt_median']:.2f} / {s['dt_p95']:.2f} / "
            f"{s['dt_max']:.0f} | {s['duplicates']} | {s['stale']} | {s['gaps_30s']} ({s['gap_time_min']:.1f} min) "
            f"| {100 * s['seconds_with_report']:.0f} % |"
        )
        if name == RADAR_FLIGHT:
            n = write_radar(rows, args.out / "radar_polar.csv")
            print(f"radar_polar.csv: {n} scans", file=sys.stderr)
    n_rows, n_aircraft = write_collection(samples, args.out / "collection_quickstart.csv.gz")
    print(f"collection_quickstart.csv.gz: {n_rows} rows, {n_aircraft} aircraft", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
