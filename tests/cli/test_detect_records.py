"""``motionsig detect`` on a user's own record: records written here by independent code (numpy and the csv
module, not ``motionsig simulate``), ISO 8601 times, renamed columns, units, the model from options,
missing samples, user codes, JSON input, x/y radar records, a threshold calibrated for the record, and the
bad-input list (one line naming file, line and column, exit 2, nothing written).

Every record has a fixed seed. Where a test asserts that the detector finds the right (mode, code phase),
the setting was checked over 20 seeds (20/20 correct, see each test) so that the assertion tests the
reading, not luck.
"""

import csv
import datetime as dt
import io
import math
import sys
import warnings

import numpy as np
import pytest

from motionsig_cli.modesig.lmp1d import table1_chips
from motionsig_cli.tables import read_table
from tests.cli.helpers import one_line_error, run, table

SIM_1D = ("simulate", "--mode", "3", "--tau-chips", "7", "--R", "1e-3", "--duration", "20", "-q")
HORIZONS = ("--horizons", "10,20")


@pytest.fixture(scope="module")
def sim_1d(tmp_path_factory):
    """A 20 s simulate record (mode 3, code phase 7 chips = 140 samples, R = 1e-3)."""
    from motionsig_cli.cli.app import main

    p = tmp_path_factory.mktemp("detect_records") / "sim.csv"
    assert main([*SIM_1D, "-o", str(p)]) == 0
    return p


@pytest.fixture(scope="module")
def sim_2d(tmp_path_factory):
    """A 12 s radar record (mode 2, code phase 5 chips = 100 samples, Fig 7 ANR pair 4)."""
    from motionsig_cli.cli.app import main

    p = tmp_path_factory.mktemp("detect_records_2d") / "radar.csv"
    args = ["simulate", "--example", "2d", "--mode", "2", "--tau-chips", "5", "--duration", "12", "-q"]
    assert main([*args, "-o", str(p)]) == 0
    return p


def _body(text: str) -> list[str]:
    """The CSV rows of a command's output (no metadata, no header)."""
    return [ln for ln in text.splitlines() if not ln.startswith("#")][1:]


def _argmax(out: str, tmp_path) -> list[tuple[int, int]]:
    t = table(out, tmp_path, "argmax.csv")
    return list(zip(map(int, t.column("mode_hat")), map(int, t.column("tau_hat")), strict=True))


def _write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    return path


# ------------------------------------------------------------------------ (a) an independent record
def closed_loop_record(seed: int, *, T=0.1, m_rho=10, f_c=0.5, a_sig=0.5, R=1e-3, K=(40.0, 10.0), n=400):
    """The 1-D closed loop with a mode signature, written from the paper's equations (1)–(3) and (53)–(55)
    with numpy (not motionsig's simulator): mode 2 of Table I, code phase 70 samples, carrier phase 0.3."""
    rng = np.random.default_rng(seed)
    chips = table1_chips()
    k = np.arange(n)
    t = k * T
    p = chips[1][((k - 70) // m_rho) % chips.shape[1]]
    w = 2 * np.pi * f_c
    z, zd = p * np.cos(w * t + 0.3), -w * p * np.sin(w * t + 0.3)
    wr = 2 * np.pi * 0.01
    r, rd = 10 * np.sin(wr * t), wr * 10 * np.cos(wr * t)
    x, v, y = 0.0, 0.0, np.empty(n)
    for i in range(n):
        y[i] = x + math.sqrt(R) * rng.standard_normal()
        u = K[0] * (-x + r[i] + a_sig * z[i]) + K[1] * (-v + rd[i] + a_sig * zd[i])
        acc = 0.01 * rng.standard_normal()
        x, v = x + T * v + 0.5 * T**2 * acc, v + T * u + T * acc
    return t, y


def test_independent_iso_record_with_renamed_columns_and_units(tmp_path, capsys):
    """A numpy record `timestamp,pos_km` (ISO 8601 times every 0.1 s, positions in km, no metadata): with
    the model given as options (m_rho 10, K 40,10, R 1e-3, f_c 0.5; T estimated from the times) the
    detector finds mode 2, code phase 70 samples (20/20 seeds correct at 20 s and 40 s)."""
    t, y = closed_loop_record(seed=1)
    t0 = dt.datetime(2026, 5, 1, 12, 0, 0, tzinfo=dt.UTC)
    stamps = [(t0 + dt.timedelta(seconds=float(s))).isoformat(timespec="milliseconds") for s in t]
    path = _write_csv(
        tmp_path / "export.csv",
        ["timestamp", "pos_km"],
        zip(stamps, (repr(float(v / 1e3)) for v in y), strict=True),
    )
    rc, out, err = run(
        capsys, "detect", str(path), "--columns", "time=timestamp,y=pos_km", "--units", "y=km",
        "--mrho", "10", "--K", "40,10", "--R", "1e-3", "--fc", "0.5", "--horizons", "20,40",
    )  # fmt: skip
    assert rc == 0, err
    assert _argmax(out, tmp_path) == [(2, 70), (2, 70)]
    meta = table(out, tmp_path).meta
    assert meta["model"]["T"] == 0.1 and meta["model"]["K"] == [40.0, 10.0] and meta["model"]["m_rho"] == 10
    sources = meta["model_sources"]
    assert sources["T"] == "record (estimated from the time column)" and sources["R"] == "option"
    assert sources["codes"] == "default (assumed)" and sources["a_sig"] == "default (assumed)"
    assert meta["input_columns"] == {"time": "timestamp", "y": "pos_km"}
    assert meta["input_units"]["y"] == "km" and meta["time_origin"] == "2026-05-01T12:00:00+00:00"
    assert "whether or not a signature is present" in err and "--pfa" in err  # the argmax is no decision


# ------------------------------------------------------------- (b) a stripped simulate record, renamed
def _stripped(sim_path, tmp_path, rename=(("t", "time_s"), ("y", "pos_m"))):
    lines = [ln for ln in sim_path.read_text().splitlines() if not ln.startswith("#")]
    header = lines[0].split(",")
    header = [dict(rename).get(c, c) for c in header]
    out = tmp_path / "stripped.csv"
    out.write_text("\n".join([",".join(header), *lines[1:]]) + "\n")
    return out


def test_stripped_simulate_record_with_options_gives_the_same_rows(sim_1d, tmp_path, capsys):
    """No metadata, t → time_s, y → pos_m, the model given as options with simulate's values: the rows are
    byte-identical to those of the original record (less its truth columns); without the options the
    model is simulate's defaults and T the time column's (0.05 s), which this record used: the same."""
    rc, original, err = run(capsys, "detect", str(sim_1d), *HORIZONS)
    assert rc == 0, err
    meta = read_table(sim_1d).meta
    stripped = _stripped(sim_1d, tmp_path)
    cols = ("--columns", "time=time_s,y=pos_m")
    model = (
        "--T", "0.05", "--mrho", "20", "--K", ",".join(repr(k) for k in meta["K"]), "--R", "1e-3",
        "--fc", "1", "--a-sig", "0.5", "--codes", "corrected", "--a-r", "10", "--f-r", "0.01", "--sigma-a", "0.01",
    )  # fmt: skip
    rc, given, err = run(capsys, "detect", str(stripped), *cols, *model, *HORIZONS)
    assert rc == 0, err
    n = 9  # horizon_s ... J0: the columns without the truth
    want = [",".join(row.split(",")[:n]) for row in _body(original)]
    assert _body(given) == want
    assert set(table(given, tmp_path).meta["model_sources"].values()) == {"option"}
    rc, defaults, err = run(capsys, "detect", str(stripped), *cols, "--R", "1e-3", *HORIZONS)
    assert rc == 0, err
    assert _body(defaults) == want
    sources = table(defaults, tmp_path).meta["model_sources"]
    assert sources["m_rho"] == "default (assumed)" and sources["K"].startswith("default (assumed)")


def test_an_option_overrides_the_record_and_says_so(sim_1d, tmp_path, capsys):
    rc, out, err = run(capsys, "detect", str(sim_1d), "--R", "1e-2", "--mrho", "20", *HORIZONS)
    assert rc == 0, err
    meta = table(out, tmp_path).meta
    assert meta["model"]["R"] == 0.01 and meta["model_sources"]["R"] == "option (the record says 0.001)"
    assert meta["model_sources"]["m_rho"] == "option (as the record)"
    assert "true_mode" in table(out, tmp_path).columns  # same codes and m_rho: the truth still applies


# ------------------------------------------------------------------------------- (c) missing samples
def _with_missing(sim_path, tmp_path, fraction=0.05, seed=3):
    """The record with ``fraction`` of its samples missing: half as empty y cells, half as deleted rows
    (never the first two rows, which fix the time grid, nor the last, which fixes the record's length)."""
    lines = sim_path.read_text().splitlines()
    first = next(i for i, ln in enumerate(lines) if not ln.startswith("#")) + 1
    n = len(lines) - first
    rng = np.random.default_rng(seed)
    picks = rng.choice(np.arange(2, n - 1), size=round(fraction * n), replace=False)
    blank, drop = set(picks[: len(picks) // 2].tolist()), set(picks[len(picks) // 2 :].tolist())
    out = lines[:first]
    yi = lines[first - 1].split(",").index("y")
    for i, ln in enumerate(lines[first:]):
        if i in drop:
            continue
        if i in blank:
            f = ln.split(",")
            f[yi] = ""
            ln = ",".join(f)
        out.append(ln)
    p = tmp_path / "missing.csv"
    p.write_text("\n".join(out) + "\n")
    return p, blank, drop, first


def test_five_percent_missing_samples_still_detect_the_mode(sim_1d, tmp_path, capsys):
    """20 of 400 samples missing (10 empty cells, 10 deleted rows): predict-only steps, and the detector
    still finds mode 3, code phase 140 at 10 s and 20 s (correct in 20/20 seeds of the missing pattern)."""
    path, blank, drop, first = _with_missing(sim_1d, tmp_path)
    rc, out, err = run(capsys, "detect", str(path), *HORIZONS)
    assert rc == 0, err
    assert _argmax(out, tmp_path) == [(3, 140), (3, 140)]
    meta = table(out, tmp_path).meta
    assert meta["missing_samples"] == 20 and "predict-only" in meta["missing_rule"]
    assert "20 of 400 samples missing" in err
    # the FFT path cannot skip a sample: one line naming the first missing one (an empty cell or a gap)
    err = one_line_error(capsys, "detect", str(path), "--method", "fft", "--Qa", "0")
    i = min(blank | drop)
    line = first + 1 + i - sum(1 for d in drop if d < i)  # the cell's line, or the line after the gap
    where = f"{path}:{line}: column 'y'" if i in blank else f"{path}:{line}: column 't': no row for t = "
    assert where in err and "use --method bank" in err, err


# ------------------------------------------------------------------------------------ (d) user codes
def test_gold_codes_from_simulate_are_detected(tmp_path, capsys):
    p = tmp_path / "gold.csv"
    rc, _, err = run(
        capsys, "simulate", "--codes", "gold:45,75:3", "--mode", "2", "--tau-chips", "4", "--R", "1e-3",
        "--duration", "20", "-q", "-o", str(p),
    )  # fmt: skip
    assert rc == 0, err
    assert read_table(p).meta["codes"] == "gold:45,75:3"
    rc, out, err = run(capsys, "detect", str(p), *HORIZONS)
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.column("correct") == ["true", "true"] and t.meta["n_candidates"] == 3 * 31


def test_a_code_table_written_by_numpy(tmp_path, capsys):
    """Four random 31-chip codes (numpy, bits 0/1) in encode's long table: simulate --codes FILE --mode 4 and
    detect --codes FILE (on the record, and on the stripped record) find mode 4. Without --codes, detect
    refuses the record, whose metadata names the file: a record never makes the tool open a file (issue 39)."""
    codes = np.random.default_rng(7).integers(0, 2, size=(4, 31))
    table_path = _write_csv(
        tmp_path / "codes.csv", ["code", "chip", "value"],
        [(f"c{i}", j, int(b)) for i, c in enumerate(codes) for j, b in enumerate(c)],
    )  # fmt: skip
    rec = tmp_path / "rec.csv"
    rc, _, err = run(
        capsys, "simulate", "--codes", str(table_path), "--mode", "4", "--tau-chips", "9", "--R", "1e-3",
        "--duration", "20", "-q", "-o", str(rec),
    )  # fmt: skip
    assert rc == 0, err
    err = one_line_error(capsys, "detect", str(rec), *HORIZONS)
    assert f"{rec}:" in err and "bad metadata: codes" in err and "--codes FILE" in err
    rc, out, err = run(capsys, "detect", str(rec), "--codes", str(table_path), *HORIZONS)
    assert rc == 0, err
    assert _argmax(out, tmp_path) == [(4, 180), (4, 180)]
    stripped = _stripped(rec, tmp_path, rename=())
    rc, again, err = run(
        capsys,
        "detect",
        str(stripped),
        "--example",
        "1d",
        "--codes",
        str(table_path),
        "--R",
        "1e-3",
        *HORIZONS,
    )  # --example 1d: the stripped record also holds the true x, and x and y read as a 2-D radar record
    assert rc == 0, err
    assert _argmax(again, tmp_path) == [(4, 180), (4, 180)]


def test_gps_codes_run_and_an_oversized_grid_is_refused(tmp_path, capsys):
    """3 GPS C/A codes (1023 chips) at m_rho 1: 3 x 1023 candidates, 6139 filters over 200 samples run
    (~0.1 GB, a few seconds) and find PRN 2 at 500 chips; with every sample phase of a 20-sample chip
    (--tau-grid samples) on 3 carriers the bank would need ~3.7e5 filters and ~5.9 GB, more than the 4 GB
    allowed: refused at once."""
    p = tmp_path / "gps.csv"
    rc, _, err = run(
        capsys, "simulate", "--codes", "gps:1-3", "--mode", "2", "--tau-chips", "500", "--mrho", "1",
        "--R", "1e-3", "--duration", "10", "-q", "-o", str(p),
    )  # fmt: skip
    assert rc == 0, err
    rc, out, err = run(capsys, "detect", str(p), "--horizons", "10")
    assert rc == 0, err
    assert _argmax(out, tmp_path) == [(2, 500)] and table(out, tmp_path).meta["n_filters"] == 6139
    err = one_line_error(
        capsys, "detect", str(p), "--horizons", "10", "--mrho", "20", "--tau-grid", "samples", "--fc-grid",
        "0.9,1,1.1",
    )  # fmt: skip
    assert "--horizons" in err and "GB" in err and "fewer codes or a coarser grid" in err


# ----------------------------------------------------------------------------------- (e) JSON input
def test_json_from_simulate_equals_the_csv_path(capsys, monkeypatch):
    outs = {}
    for fmt in ("csv", "json"):
        rc, rec, err = run(capsys, *SIM_1D, "-f", fmt)
        assert rc == 0, err
        monkeypatch.setattr(sys, "stdin", io.StringIO(rec))
        rc, outs[fmt], err = run(capsys, "detect", "-", *HORIZONS, "-q")
        assert rc == 0, err
    assert outs["json"] == outs["csv"]


# -------------------------------------------------------------------------- (f) a radar record in x, y
def test_cartesian_record_equals_polar_record(sim_2d, tmp_path, capsys):
    """The same radar measurements as (range, bearing) and as (x, y) = range (cos, sin) bearing, both
    written by numpy without metadata: the statistics agree within 1e-12 (relative); x, y also in km
    with header units, and the bearing in degrees, give the same answer."""
    t = read_table(sim_2d)
    time, rng, brg = t.numeric("t"), t.numeric("range"), t.numeric("bearing")
    model = (
        "--R-range",
        repr(t.meta["R_range"]),
        "--R-bearing",
        repr(t.meta["R_bearing"]),
        "--horizons",
        "6,12",
    )
    files = {
        "polar": (["time", "range", "bearing"], zip(time, rng, brg, strict=True)),
        "cartesian": (["time", "x", "y"], zip(time, rng * np.cos(brg), rng * np.sin(brg), strict=True)),
        "km_deg": (
            ["time", "range [km]", "bearing [deg]"],
            zip(time, rng / 1e3, np.degrees(brg), strict=True),
        ),
    }
    stats = {}
    for name, (header, rows) in files.items():
        path = _write_csv(tmp_path / f"{name}.csv", header, ([repr(float(v)) for v in r] for r in rows))
        rc, out, err = run(capsys, "detect", str(path), *model)
        assert rc == 0, err
        res = table(out, tmp_path)
        stats[name] = res.numeric("statistic")
        assert res.meta["n_filters"] == 187 and res.meta["filter"] == "ukf"
        if name == "cartesian":
            assert "hypot(x, y)" in res.meta["measurement"]
        assert _argmax(out, tmp_path)[-1] == (2, 100)  # 12 s: ~100 % correct in the Fig 7 Monte Carlo
    np.testing.assert_allclose(stats["cartesian"], stats["polar"], rtol=1e-12, atol=0)
    np.testing.assert_allclose(stats["km_deg"], stats["polar"], rtol=1e-9, atol=0)


# ------------------------------------------------------------------------------ a calibrated threshold
def test_pfa_calibrates_a_threshold_for_the_record(sim_1d, tmp_path, capsys):
    """--pfa 0.01 with 500 null records (FFT path): the signature record's max Lambda lies far above the
    threshold (7 vs ~0.004), an H0 record of the same model (seed 5) lies below it (a 1 % false alarm
    chance for a given seed, fixed here); the thresholds are the calibration's, in the metadata."""
    args = ("--method", "fft", "--Qa", "0", "--pfa", "0.01", "--null-trials", "500", *HORIZONS)
    rc, out, err = run(capsys, "detect", str(sim_1d), *args)
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.columns[-2:] == ("threshold", "signature_present")
    assert t.column("signature_present") == ["true", "true"]
    cal = t.meta["threshold_calibration"]
    assert cal["pfa"] == 0.01 and cal["null_trials"] == 500
    assert list(t.numeric("threshold")) == cal["thresholds"] and t.meta["threshold"] == cal["thresholds"]
    assert min(t.numeric("statistic") / t.numeric("threshold")) > 100
    h0 = tmp_path / "h0.csv"
    rc, _, err = run(capsys, "simulate", "--no-signature", "--R", "1e-3", "--duration", "20", "--seed", "5",
                     "-q", "-o", str(h0))  # fmt: skip
    assert rc == 0, err
    rc, out, err = run(capsys, "detect", str(h0), *args)
    assert rc == 0, err
    assert table(out, tmp_path).column("signature_present") == ["false", "false"]
    assert "signature absent" in err


def test_pfa_on_a_radar_record_runs_the_sigma_point_null_records(sim_2d, tmp_path, capsys):
    rc, out, err = run(
        capsys, "detect", str(sim_2d), "--horizons", "2", "--pfa", "0.1", "--null-trials", "20"
    )
    assert rc == 0, err
    t = table(out, tmp_path)
    assert (
        t.meta["threshold_calibration"]["filter"] == "ukf"
        and t.meta["threshold_calibration"]["null_trials"] == 20
    )
    assert t.columns[-2:] == ("threshold", "signature_present")


# ------------------------------------------------------------------------------------------ bad input
def _rows(n: int, T: float = 0.05) -> str:
    return "".join(f"{k * T!r},{math.sin(k):.6f}\n" for k in range(n))


# fmt: off
BAD_FILES = [
    # (name, content, extra args, needles: "{f}" is the file's path)
    ("header.csv", "foo,bar\n1,2\n3,4\n", (), ("{f}:1: missing column 'time'", "--columns time=NAME")),
    ("text.csv", "t,y\n0,1\n0.05,abc\n0.1,2\n", (), ("{f}:3: column 'y': 'abc' is not a number",)),
    ("inf.csv", "t,y\n0,1\n0.05,inf\n0.1,2\n", (), ("{f}:3: column 'y': 'inf' is not finite",)),
    ("dup.csv", "t,y\n0,1\n0.05,2\n0.05,3\n0.1,2\n", (), ("{f}:4: column 't': time is not increasing",)),
    ("dec.csv", "t,y\n0,1\n0.1,2\n0.05,3\n", (), ("{f}:4: column 't': time is not increasing", "backwards")),
    ("time.csv", "t,y\nnoon,1\n0.05,2\n", (), ("{f}:2: column 't'", "ISO 8601")),
    ("unit.csv", "t,y [furlong]\n0,1\n0.05,2\n", (), ("{f}:1: column 'y [furlong]': unknown length unit",)),
    ("empty.csv", "", (), ("{f}: no header row",)),
    ("header_only.csv", "t,y\n", (), ("{f}: need at least 2 samples",)),
    ("json.csv", '{"meta": {}, "data": [\n', (), ("{f}:", "not valid JSON")),
    ("short.csv", "t,y\n" + _rows(40), ("--horizons", "10"), ("--horizons", "longer than the record (2 s)")),
    ("span.csv", "t,y\n0,1\n0.05,2\n0.1,3\n100000,4\n", (), ("{f}:5: column 't'", "2000001 samples", "more than 1000000")),
    ("nan.csv", "t,y\n0,\n0.05,nan\n0.1,NA\n", (), ("{f}: no measurement: every sample", "missing")),
    ("offgrid.csv", "t,y\n" + _rows(40), ("--T", "0.07"), ("--T", "does not fit the record's times")),
    ("range0.csv", "t,range,bearing\n0,70,0.1\n0.05,0,0.1\n", (), ("{f}:3: column 'range': range 0 <= 0: the target is at the radar",)),
    ("range_neg.csv", "t,range [km],bearing\n0,1,0.1\n0.05,-0.5,0.1\n", (), ("{f}:3: column 'range [km]': range -0.5 km is not > 0",)),
    ("range_neg_m.csv", "t,range,bearing\n0,70,0.1\n0.05,-5,0.1\n", (), ("{f}:3: column 'range': range -5 m is not > 0",)),
    ("huge_y.csv", "t,y\n" + _rows(100) + "5.0,1e300\n", (), ("{f}:102: column 'y': |y| 1e+300 m exceeds 1e+09 m",)),
    ("huge_neg_y.csv", "t,y [km]\n0,1\n0.05,-2e6\n0.1,1\n", (), ("{f}:3: column 'y [km]': |y| 2000000 km = 2e+09 m exceeds 1e+09 m",)),
    ("huge_range.csv", "t,range,bearing\n0,70,0.1\n0.05,1e150,0.1\n0.1,70,0.1\n", (), ("{f}:3: column 'range': |range| 1e+150 m exceeds",)),
    ("huge_x.csv", "t,x,y\n0,70,1\n0.05,70,-1e10\n0.1,70,1\n", (), ("{f}:3: column 'y': |y| 1e+10 m exceeds",)),
    (
        "bearing.csv", "t,range,bearing\n0,70,0.1\n0.05,70,57\n", (),
        ("{f}:3: column 'bearing': bearing 57 is outside", "degrees in a column labelled radians"),
    ),
    ("origin.csv", "t,x,y\n0,70,1\n0.05,0,0\n", (), ("{f}:3: column 'x'", "at the radar")),
    ("nobearing.csv", "t,range\n0,70\n0.05,70\n", (), ("{f}:1: missing column 'bearing'",)),
    ("cols.csv", "t,y\n" + _rows(40), ("--columns", "y=pos"), ("{f}:1: no column 'pos' for --columns y=pos",)),
    ("role.csv", "t,y\n" + _rows(40), ("--columns", "speed=v"), ("--columns", "'speed' is not a column")),
    ("units.csv", "t,y\n" + _rows(40), ("--units", "y=furlong"), ("--units", "is not a length unit")),
    ("other.csv", "t,y\n" + _rows(40), ("--R-range", "1"), ("--R-range", "applies to the 2d example only")),
    ("codes.csv", "t,y\n" + _rows(40), ("--codes", "gold:45,51"), ("--codes", "not a preferred partner")),
    ("k.csv", "t,y\n" + _rows(40), ("--K", "1,2,3"), ("--K", "is not a list of two numbers")),
    ("both.csv", "t,y\n" + _rows(40), ("--pfa", "0.1", "--threshold", "1"), ("--pfa", "not both")),
    ("meta.csv", '# command: "simulate"\n# example: "1d"\n# T: 0.05\nt,y\n' + _rows(40), (), ("missing metadata 'm_rho'",)),
    ("badmeta.csv", "# m_rho: 2.5\nt,y\n" + _rows(40), (), ("{f}:1: bad metadata: m_rho = 2.5 is not an integer",)),
    ("example.csv", '# example: "3d"\nt,y\n' + _rows(40), (), ("{f}: unknown example '3d'",)),
]
# fmt: on


@pytest.mark.parametrize(("name", "content", "args", "needles"), BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_input_is_one_line_naming_file_line_and_column(tmp_path, capsys, name, content, args, needles):
    path = tmp_path / name
    path.write_text(content)
    target = tmp_path / "out.csv"
    err = one_line_error(capsys, "detect", str(path), *args, "-o", str(target))
    for needle in needles:
        assert needle.format(f=path) in err, err
    assert not target.exists()


def test_a_record_of_ten_million_rows_is_refused_while_it_is_read(tmp_path, capsys):
    """The record limit is 10^6 samples: reading stops at the first line beyond it (line 1 000 002)."""
    path = tmp_path / "huge.csv"
    with open(path, "wb") as f:
        f.write(b"t,y\n")
        f.write(b"0,0\n" * 10_000_000)
    err = one_line_error(capsys, "detect", str(path))
    assert f"{path}:1000002: more than 1000000 data rows" in err


def test_a_bad_code_table_names_its_file_and_line(tmp_path, capsys):
    bad = tmp_path / "codes.csv"
    bad.write_text("code,chip,value\na,0,1\na,1,2\n")
    rec = tmp_path / "rec.csv"
    rec.write_text("t,y\n" + _rows(40))
    err = one_line_error(capsys, "detect", str(rec), "--codes", str(bad))
    assert str(bad) in err
    err = one_line_error(capsys, "detect", str(rec), "--codes", str(tmp_path / "none.csv"))
    assert "--codes" in err and "neither a code set nor an existing file" in err


def test_record_options_are_refused_with_the_monte_carlo(capsys):
    # (the model options --T, --mrho, --K, --a-r, … are the Monte Carlo's own: tests/cli/test_detect_options.py)
    for opt in (("--R", "1e-3"), ("--columns", "time=t"), ("--codes", "gold:45,75:3"), ("--f-r", "0.1")):
        err = one_line_error(capsys, "detect", "--montecarlo", "--trials", "1", *opt)
        assert opt[0] in err and "applies to a record" in err


@pytest.mark.parametrize(
    ("header", "plain", "bad", "column"),
    [
        ("t,y", "1e-5", "{v}", "y"),
        ("t,range,bearing", "70,0.1", "{v},0.1", "range"),
        ("t,x,y", "70,3", "70,{v}", "y"),
    ],
    ids=["1d", "polar", "cartesian"],
)
def test_a_magnitude_beyond_the_bound_is_refused_and_one_at_it_keeps_the_statistic_finite(
    tmp_path, capsys, header, plain, bad, column
):
    """A fill value such as 1e300 made the statistic NaN (overflowing squares) and exited 0; beyond 1e9 m a
    position or range is refused with its line and column. At the bound itself the filters' arithmetic
    stays finite: the run succeeds without a RuntimeWarning and every statistic is finite (the bound is
    not arbitrary). One implausible sample at line 102 (sample 100) of an otherwise constant record."""

    def record(name: str, v: str):
        rows = "".join(f"{k * 0.05!r},{bad.format(v=v) if k == 100 else plain}\n" for k in range(240))
        (tmp_path / name).write_text(header + "\n" + rows)
        return tmp_path / name

    at, beyond = record("at.csv", "1e9" if column == "range" else "-1e9"), record("beyond.csv", "1.0000001e9")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a RuntimeWarning (overflow, invalid value) fails the test
        rc, out, err = run(capsys, "detect", str(at), "--horizons", "10")
    assert rc == 0, err
    assert all(math.isfinite(float(v)) for v in table(out, tmp_path).column("statistic"))
    target = tmp_path / "out.csv"
    err = one_line_error(capsys, "detect", str(beyond), "--horizons", "10", "-o", str(target))
    assert f"{beyond}:102: column '{column}': |{column}| 1.0000001e+09 m exceeds 1e+09 m" in err
    assert not target.exists()
