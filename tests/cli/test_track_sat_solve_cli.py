"""``motionsig track-sat solve`` end to end on records written here with numpy and the csv module (a wide-area
multilateration network around an airport, a transmitter with a drifting clock), and its one-line refusals."""

import csv
import json
import math

import numpy as np
import pymap3d
import pytest

from tests.cli.helpers import one_line_error, run, table

C = 299_792_458.0
AIRPORT = (48.3538, 11.7861, 453.0)
STATIONS = {"MUC1": (0, 0, 0), "FRS": (15e3, 2e3, 30), "ERD": (-12e3, 8e3, -20), "MOO": (3e3, -14e3, 60),
            "NEU": (-6e3, -9e3, 10), "LAN": (9e3, 12e3, -5)}  # fmt: skip
"""Six receivers: east, north, up [m] about the airport reference point."""
E = 120
SIGMA_NS = 10.0
SIGMA0_NS = 20.0


def write_example(tmp_path, *, outage=range(60, 70), seed=7):
    """The worked example: stations.csv (WGS-84 latitude, longitude, altitude) and toa.csv (epoch, time,
    station, toa [s], sigma [ns]) of a transmitter flying over the network at 2–4 km with a clock that
    drifts (x_n = Σ w_i + n a_0, σ0 = 20 ns per 1 s epoch) and emits 100 µs late; TOAs with 10 ns noise;
    three stations miss the pulses of ``outage`` (the report's three-receiver case), one TOA is empty.
    Returns the truth: positions (E, 3) ECEF [m] and clock offsets (E,) [s]."""
    rng = np.random.default_rng(seed)
    names = list(STATIONS)
    enu = np.array([STATIONS[n] for n in names], float)
    lat, lon, alt = pymap3d.enu2geodetic(enu[:, 0], enu[:, 1], enu[:, 2], *AIRPORT)
    S = np.stack(pymap3d.geodetic2ecef(lat, lon, alt), axis=-1)
    with open(tmp_path / "stations.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["station", "latitude", "longitude", "altitude"])
        w.writerows(
            [n, repr(float(a)), repr(float(b)), repr(float(h))]
            for n, a, b, h in zip(names, lat, lon, alt, strict=True)
        )
    path = np.column_stack([np.linspace(-20e3, 20e3, E), np.linspace(5e3, -5e3, E), np.linspace(2e3, 4e3, E)])
    truth = np.stack(pymap3d.enu2ecef(path[:, 0], path[:, 1], path[:, 2], *AIRPORT), axis=-1)
    s0 = SIGMA0_NS * 1e-9
    x = (
        np.concatenate([[0.0], np.cumsum(rng.standard_normal(E - 1) * s0)])
        + np.arange(E) * rng.standard_normal() * s0
    )
    offset = 1e-4 + x
    t = 1000.0 + np.arange(E)
    with open(tmp_path / "toa.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["epoch", "time", "station", "toa", "sigma [ns]"])
        for n in range(E):
            for k, name in enumerate(names):
                if n in outage and k >= 3:
                    continue
                toa = (
                    t[n]
                    + offset[n]
                    + np.linalg.norm(truth[n] - S[k]) / C
                    + rng.standard_normal() * SIGMA_NS * 1e-9
                )
                w.writerow(
                    [n, repr(float(t[n])), name, "" if (n, k) == (30, 0) else repr(float(toa)), SIGMA_NS]
                )
    return truth, offset


def _col(t, name):
    return np.array([np.nan if v in ("", None) else float(v) for v in t.column(name)])


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    """The example with its 3-station outage (epochs 60–69)."""
    d = tmp_path_factory.mktemp("wam")
    truth, offset = write_example(d)
    return d, truth, offset


@pytest.fixture(scope="module")
def plain(tmp_path_factory):
    """The example without the outage (every epoch has a snapshot fix)."""
    d = tmp_path_factory.mktemp("wam_plain")
    truth, offset = write_example(d, outage=range(0))
    return d, truth, offset


def test_snapshot_fixes_are_consistent_with_their_covariance(capsys, tmp_path, plain):
    """Each epoch's position error, normalised by the fix's own covariance (--full-covariance), is χ² with 3
    degrees of freedom: over the 120 epochs its mean is 3 within 4 standard errors (√(6/120) = 0.22); the
    clock offsets likewise (χ²₁)."""
    d, truth, offset = plain
    rc, out, err = run(capsys, "track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"),
                       "--full-covariance")  # fmt: skip
    assert rc == 0, err
    assert "120 snapshot fix(es)" in err
    t = table(out, tmp_path)
    assert t.meta["command"] == "track-sat solve" and t.meta["measurement"] == "toa"
    assert t.meta["covariance"].startswith("(H'WH)^-1 with W = 1/sigma^2")
    fix = np.array([c is not None and c != "" for c in t.column("x_m")])
    assert fix.all()
    e = np.column_stack([_col(t, f"{a}_m") for a in "xyz"])[fix] - truth[fix]
    names = ("x", "y", "z")
    P = np.array(
        [[_col(t, f"cov_{names[min(i, j)]}_{names[max(i, j)]}_m2")[fix] for j in range(3)] for i in range(3)]
    )
    chi2 = np.einsum("ni,ijn,nj->n", e, np.linalg.inv(P.transpose(2, 0, 1)).transpose(1, 2, 0), e)
    assert abs(chi2.mean() - 3.0) < 4 * math.sqrt(6 / fix.sum()), chi2.mean()
    zc = (_col(t, "clock_offset_s")[fix] - offset[fix]) / _col(t, "sd_clock_offset_s")[fix]
    assert abs(np.mean(zc**2) - 1.0) < 4 * math.sqrt(2 / fix.sum())
    alt = pymap3d.ecef2geodetic(*truth[fix].T)[2]
    assert np.max(np.abs(_col(t, "altitude_m")[fix] - alt)) < 6 * np.max(_col(t, "sd_up_m")[fix])
    assert _col(t, "n_receivers").tolist()[29:31] == [6, 5]


def test_clock_tracking_beats_the_snapshot_and_bridges_the_outage(capsys, tmp_path, example):
    """With --clock track the report's tracker runs beside the fixes: its clock error is within its own sd
    (χ² mean 1 within 4 SE over the 120 epochs), smaller than the snapshot's, and the 10 epochs with three
    stations get positions (the report's outage case) with errors within their sd."""
    d, truth, offset = example
    rc, out, err = run(capsys, "track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"),
                       "--clock", "track", "--sigma0", str(SIGMA0_NS))  # fmt: skip
    assert rc == 0, err
    assert "1 init, 109 update, 10 outage" in err
    t = table(out, tmp_path)
    assert t.column("track_mode")[58:72] == ["update"] * 2 + ["outage"] * 10 + ["update"] * 2
    zc = (_col(t, "track_clock_offset_s") - offset) / _col(t, "track_sd_clock_offset_s")
    assert abs(np.mean(zc**2) - 1.0) < 4 * math.sqrt(2 / E)
    fix = np.isfinite(_col(t, "clock_offset_s"))
    snap = np.sqrt(np.mean((_col(t, "clock_offset_s")[fix] - offset[fix]) ** 2))
    trk = np.sqrt(np.mean((_col(t, "track_clock_offset_s")[fix] - offset[fix]) ** 2))
    assert trk < 0.8 * snap
    pe = np.column_stack([_col(t, f"track_{a}_m") for a in "xyz"]) - truth
    psd = np.column_stack([_col(t, f"track_sd_{a}_m") for a in "xyz"])
    assert np.all(np.isfinite(pe)) and np.mean((pe / psd) ** 2) < 1.0 + 4 * math.sqrt(2 / (3 * E))
    assert t.meta["track"]["sigma0_ns"] == SIGMA0_NS and t.meta["track"]["modes"]["outage"] == 10


def test_report_units_json_and_residuals(capsys, tmp_path, plain):
    d, _, _ = plain
    args = ("track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"), "-q")
    rc, si, _ = run(capsys, *args)
    rc2, rep, _ = run(capsys, *args, "--units", "report", "-f", "json")
    assert rc == rc2 == 0
    doc = json.loads(rep)
    assert doc["meta"]["units"] == {"length": "ft", "time": "ns", "residual": "ns", "system": "report"}
    t = table(si, tmp_path)
    x_ft = np.array([np.nan if r["x_ft"] is None else r["x_ft"] for r in doc["data"]])
    np.testing.assert_allclose(x_ft, _col(t, "x_m") / 0.3048, rtol=1e-12)
    off_ns = np.array([np.nan if r["clock_offset_ns"] is None else r["clock_offset_ns"] for r in doc["data"]])
    np.testing.assert_allclose(off_ns, _col(t, "clock_offset_s") * 1e9, rtol=1e-12)
    # the same record through standard input, as JSON
    src = tmp_path / "toa.json"
    rc, js, _ = run(capsys, "track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"),
                    "--view", "residuals", "-f", "json", "-q")  # fmt: skip
    assert rc == 0
    rows = json.loads(js)["data"]
    assert len(rows) == 6 * E and rows[0]["receiver"] == "MUC1" and rows[0]["line"] == 2
    assert [r["measured"] for r in rows].count(False) == 1  # the empty TOA
    z = np.array([r["normalised_residual"] for r in rows if r["normalised_residual"] is not None])
    assert abs(np.sum(z**2) / (E * 2 - 1) - 1.0) < 4 * math.sqrt(2 / (2 * E))  # Σ r'Wr / Σ (K − 4) ≈ 1
    # the residual view read back as the input of nothing else: JSON the readers accept
    src.write_text(js)
    assert json.loads(src.read_text())["meta"]["view"] == "residuals"


def test_positions_in_the_record_and_from_stdin(capsys, tmp_path, plain, monkeypatch):
    """The record may carry the receivers' positions itself; '-' reads it from standard input."""
    import io
    import sys

    d, _, _ = plain
    st = {r["station"]: r for r in csv.DictReader(open(d / "stations.csv"))}
    lines = list(csv.reader(open(d / "toa.csv")))
    text = io.StringIO()
    w = csv.writer(text)
    w.writerow([*lines[0], "lat", "lon", "alt"])
    for r in lines[1:]:
        s = st[r[2]]
        w.writerow([*r, s["latitude"], s["longitude"], s["altitude"]])
    rc, a, _ = run(
        capsys, "track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"), "-q"
    )
    monkeypatch.setattr(sys, "stdin", io.StringIO(text.getvalue()))
    rc2, b, err = run(capsys, "track-sat", "solve", "-", "-q")
    assert rc == rc2 == 0, err
    ta, tb = table(a, tmp_path, "a.csv"), table(b, tmp_path, "b.csv")
    np.testing.assert_allclose(_col(ta, "x_m"), _col(tb, "x_m"), rtol=0, atol=1e-6)
    assert tb.meta["input"] == "<stdin>" and "receivers" not in tb.meta


def test_a_json_record_and_the_covariance_scalings(capsys, tmp_path, plain):
    """The record as the JSON document the commands write (numbers, null for the missed TOA) gives the same
    fixes; without σ the covariance is scaled by the pooled variance factor, which is ≈ 1 when the σ the
    noise was drawn with is given (4 SE: √(2/239) = 0.09), and 'epoch' scales each epoch by its own."""
    d, _, _ = plain
    rows = list(csv.DictReader(open(d / "toa.csv")))
    doc = {"meta": {"note": "written by the test"}, "columns": list(rows[0]),
           "data": [{k: (None if v == "" else float(v) if k != "station" else v) for k, v in r.items()} for r in rows]}  # fmt: skip
    (tmp_path / "toa.json").write_text(json.dumps(doc))
    base = ("track-sat", "solve", "--receivers", str(d / "stations.csv"), "-q")
    rc, a, _ = run(capsys, *base[:2], str(d / "toa.csv"), *base[2:])
    rc2, b, err = run(capsys, *base[:2], str(tmp_path / "toa.json"), *base[2:])
    assert rc == rc2 == 0, err
    ta, tb = table(a, tmp_path, "a.csv"), table(b, tmp_path, "b.csv")
    np.testing.assert_array_equal(_col(ta, "x_m"), _col(tb, "x_m"))
    rc, p, _ = run(capsys, *base[:2], str(d / "toa.csv"), *base[2:], "--covariance", "pooled")
    tp = table(p, tmp_path, "p.csv")
    assert abs(tp.meta["variance_factor"] - 1.0) < 4 * math.sqrt(2 / (2 * E - 1))
    np.testing.assert_allclose(
        _col(tp, "sd_x_m"), _col(ta, "sd_x_m") * math.sqrt(tp.meta["variance_factor"]), rtol=1e-9
    )
    rc, q, _ = run(capsys, *base[:2], str(d / "toa.csv"), *base[2:], "--covariance", "epoch")
    assert (
        rc == 0
        and "each epoch's a-posteriori variance factor" in table(q, tmp_path, "q.csv").meta["covariance"]
    )


def test_a_start_below_the_network_gives_the_mirror_fixes_and_a_warning(capsys, tmp_path, plain):
    """--start below the stations' plane selects the mirror-image fixes below ground; their summed χ² is
    far worse than that of the fixes above, and the command says so (the output is still written)."""
    d, truth, _ = plain
    args = ("track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"))
    rc, out, err = run(capsys, *args, "--start", "48.3,11.8,-3000")
    assert rc == 0 and "warning: the mirror images of the fixes in the receivers' plane fit better" in err
    t = table(out, tmp_path)
    assert np.all(_col(t, "altitude_m") < 0)
    rc, out, err = run(capsys, *args)
    assert rc == 0 and "warning" not in err
    t = table(out, tmp_path, "up.csv")
    assert t.meta["fixes"]["not_converged"] == 0
    err_m = np.linalg.norm(np.column_stack([_col(t, f"{a}_m") for a in "xyz"]) - truth, axis=1)
    assert np.max(err_m) < 6 * np.max(
        np.sqrt(_col(t, "sd_x_m") ** 2 + _col(t, "sd_y_m") ** 2 + _col(t, "sd_z_m") ** 2)
    )


def test_help_lists_the_command(capsys):
    rc, out, _ = run(capsys, "track-sat", "--help")
    assert rc == 0 and "solve" in out
    rc, out, _ = run(capsys, "track-sat", "solve", "--help")
    assert rc == 0 and "--receivers" in out and "--clock" in out and "--units" in out


# --- bad input: one line, exit 2, nothing written -------------------------------------------------------


def _files(tmp_path, plain, *, toa=None, stations=None):
    d, _, _ = plain
    m = tmp_path / "m.csv"
    m.write_text(toa(open(d / "toa.csv").read()) if toa else open(d / "toa.csv").read())
    s = tmp_path / "s.csv"
    s.write_text(stations(open(d / "stations.csv").read()) if stations else open(d / "stations.csv").read())
    return m, s


def _replace_line(n, new):
    def f(text):
        rows = text.splitlines()
        rows[n - 1] = new(rows[n - 1]) if callable(new) else new
        return "\n".join(rows) + "\n"

    return f


def _km(text):
    rows = list(csv.reader(text.splitlines()))
    out = ["station,x,y,z"]
    for r in rows[1:]:
        x, y, z = pymap3d.geodetic2ecef(float(r[1]), float(r[2]), float(r[3]))
        out.append(f"{r[0]},{x / 1e3},{y / 1e3},{z / 1e3}")
    return "\n".join(out) + "\n"


def _line_of_stations(text):
    out = ["station,x,y,z"] + [
        f"{n},{6378137.0 + 10 * k},{1000.0 * k},{2000.0 * k}" for k, n in enumerate(STATIONS)
    ]
    return "\n".join(out) + "\n"


BAD = {
    "coincident receivers": ({"stations": lambda s: s.replace(s.splitlines()[3].split(",", 1)[1], s.splitlines()[2].split(",", 1)[1])},
                             (), r"s.csv:4: column 'latitude': receivers 'FRS' \(line 3\) and 'ERD' \(line 4\) coincide"),
    "singular geometry": ({"stations": _line_of_stations}, (), r"m.csv:2: column 'station': epoch 0: the geometry is singular"),
    "time going backwards": ({"toa": _replace_line(8, lambda r: r.replace("1001.0,", "999.0,", 1))}, (),
                             r"m.csv:8: column 'time': epoch 1 has two times: 999.0 s here, 1001.0 s at line 9"),
    "odd time in an epoch": ({"toa": _replace_line(4, lambda r: r.replace("1000.0,", "1000.5,", 1))}, (),
                             r"m.csv:4: column 'time': epoch 0 has two times: 1000.5 s here, 1000.0 s at line 2 and 4 more"),
    "positions in km": ({"stations": _km}, (), r"s.csv:2: column 'x': positions look like kilometres: \|r\| = 6366.\d+ m"),
    "unknown receiver": ({"toa": _replace_line(5, lambda r: r.replace("MOO", "XYZ"))}, (), r"m.csv:5: column 'station': unknown receiver 'XYZ'"),
    "missing column": ({"toa": lambda s: s.replace("station", "stn", 1)}, (), r"m.csv:1: missing column 'receiver'"),
    "stations without labels": ({"stations": lambda s: "\n".join(r.split(",", 1)[1] for r in s.splitlines()) + "\n"}, (),
                                r"s.csv:1: no receiver column: map one with --receivers-columns receiver=NAME \(columns: latitude, "),
    "stations column not there": ({}, ("--receivers-columns", "receiver=site_no"),
                                  r"s.csv:1: no column 'site_no' for --receivers-columns receiver=site_no"),
    "text in number": ({"toa": _replace_line(4, lambda r: r.rsplit(",", 2)[0] + ",12:00:00.1,10")}, (), r"m.csv:4: column 'toa': '12:00:00.1' is not a number"),
    "empty file": ({"toa": lambda s: ""}, (), r"m.csv: no header row"),
    "unknown unit": ({}, ("--units", "toa=fortnight"), r"Invalid value for --units: 'toa=fortnight' is not a time unit"),
    "unknown output units": ({}, ("--units", "imperial"), r"Invalid value for --units: 'imperial' is neither si, report nor role=unit"),
    "sigma with an unknown unit": ({}, ("--sigma", "5parsec"), r"Invalid value for --sigma: '5parsec' has unit 'parsec': not a time or length unit"),
    "plain sigma for TOAs is seconds": ({}, ("--sigma", "10"), r"Invalid value for --sigma: '10' is more than one second of light time \(a number without a unit is in the measurement's unit, s here: 10 ns is 10ns\)"),
    "false-alarm probability": ({}, ("--p-fa", "0"), r"Invalid value for --p-fa: 0 is not in \(0, 0.5\]"),
    "earth rotation with tracking": ({}, ("--earth-rotation", "--clock", "track"), r"Invalid value for --earth-rotation: True applies to the snapshot fixes: not with --clock track"),
    "sigma0 without tracking": ({}, ("--sigma0", "5"), r"Invalid value for --sigma0: 5 applies to the clock tracker: add --clock track"),
    "tracking without sigma": ({"toa": lambda s: s.replace(",sigma [ns]", "").replace(",10.0\n", "\n")}, ("--clock", "track"),
                               r"Invalid value for --sigma: None is needed by --clock track"),
    "bad start": ({}, ("--start", "48,11"), r"Invalid value for --start: expected latitude,longitude,altitude"),
    "receivers columns without receivers": ({}, ("--receivers-columns", "x=east"), None),
}  # fmt: skip


def test_an_epoch_with_three_receivers_gets_a_no_fix_row_and_the_run_goes_on(capsys, tmp_path, plain):
    m, s = _files(tmp_path, plain, toa=lambda s: "\n".join(r for i, r in enumerate(s.splitlines(), 1) if i not in (363, 364, 365)) + "\n")  # fmt: skip
    rc, out, err = run(capsys, "track-sat", "solve", str(m), "--receivers", str(s))
    assert rc == 0, err
    assert "1 epoch(s) without a fix (too few receivers: epoch 60)" in err
    t = table(out, tmp_path)
    rows = [dict(zip(t.columns, r, strict=True)) for r in t.rows]
    assert rows[60]["status"] == "no fix: 3 receiver(s), a fix needs 4" and rows[60]["x_m"] in (None, "")
    assert sum(r["status"] == "fix" for r in rows) == 119
    assert t.meta["fixes"]["no_fix"] == {"too few receivers": 1}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_input_is_one_line_with_exit_code_2(capsys, tmp_path, plain, name):
    kw, extra, match = BAD[name]
    m, s = _files(tmp_path, plain, **kw)
    out = tmp_path / "out.csv"
    rx = ("--receivers", str(s)) if name != "receivers columns without receivers" else ()
    err = one_line_error(capsys, "track-sat", "solve", str(m), *rx, *extra, "-o", str(out))
    assert err.startswith("motionsig track-sat solve: error: ") or "Invalid value" in err, err
    if match is not None:
        import re

        assert re.search(match, err), err
    assert not out.exists()  # no partial output


def test_too_many_rows_are_refused_while_reading(capsys, tmp_path, example):
    """A record beyond the row limit (10^6) is refused at the first row beyond it, before it is held."""
    from motionsig_cli.atc10.toa_solve import MAX_MEASUREMENTS

    d, _, _ = example
    m = tmp_path / "long.csv"
    with open(m, "w") as f:
        f.write("epoch,station,toa\n")
        f.writelines(f"{i // 6},{list(STATIONS)[i % 6]},0.0001\n" for i in range(MAX_MEASUREMENTS + 1))
    err = one_line_error(capsys, "track-sat", "solve", str(m), "--receivers", str(d / "stations.csv"))
    assert f"long.csv:{MAX_MEASUREMENTS + 2}: more than {MAX_MEASUREMENTS} data rows" in err


def test_the_output_may_not_overwrite_the_record(capsys, tmp_path, example):
    d, _, _ = example
    m = tmp_path / "m.csv"
    m.write_text(open(d / "toa.csv").read())
    err = one_line_error(
        capsys, "track-sat", "solve", str(m), "--receivers", str(d / "stations.csv"), "-o", str(m)
    )
    assert "--out" in err and "is the measurement record" in err


def test_the_summary_counts_converged_fixes_only(capsys, tmp_path, plain):
    """With one Gauss-Newton step no epoch converges: the summary says so (not "120 snapshot fix(es)")."""
    d, _, _ = plain
    rc, out, err = run(capsys, "track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv"),
                       "--max-iter", "1")  # fmt: skip
    assert rc == 0, err
    assert "no snapshot fix: none of 120 epoch(s) converged" in err and "snapshot fix(es)" not in err
    assert table(out, tmp_path).meta["fixes"]["not_converged"] == 120


def test_unix_nanosecond_records_solve_end_to_end(capsys, tmp_path, plain):
    """The worked example with its times and TOAs as integer nanoseconds since the Unix epoch (``time [ns]``,
    ``toa [ns]``, written here with Python integers; float64 would lose up to 128 ns = 38 m there): each fix
    differs from that of the record in seconds only by the TOAs' nanosecond rounding δρ (|δT| ≤ 0.5 ns):
    ‖δp‖ ≤ PDOP ‖δρ‖₂ per epoch (equal weights: δp = pinv(H)[:3] δρ, whose spectral norm is at most its
    Frobenius norm, the PDOP), to first order (+1 mm). The metadata states the first time."""
    from decimal import Decimal

    d, _, _ = plain
    rows = list(csv.reader(open(d / "toa.csv")))
    t0 = 1_777_629_600 * 10**9
    out_rows = ["epoch,time [ns],station,toa [ns],sigma [ns]"]
    drho2 = np.zeros(E)
    for r in rows[1:]:
        t = t0 + int(Decimal(r[1]) * 10**9)
        toa = ""
        if r[3]:
            exact = Decimal(r[3]) * 10**9
            toa = str(t0 + int(exact.to_integral_value()))
            drho2[int(r[0])] += (float(exact.to_integral_value() - exact) * 1e-9 * C) ** 2
        out_rows.append(f"{r[0]},{t},{r[2]},{toa},{r[4]}")
    m = tmp_path / "ns.csv"
    m.write_text("\n".join(out_rows) + "\n")
    assert "1777630600000000000,MUC1,17776306000001" in m.read_text()
    rc, out, err = run(capsys, "track-sat", "solve", str(m), "--receivers", str(d / "stations.csv"))
    assert rc == 0, err
    t = table(out, tmp_path)
    rc, ref_out, err = run(
        capsys, "track-sat", "solve", str(d / "toa.csv"), "--receivers", str(d / "stations.csv")
    )
    ref = table(ref_out, tmp_path, "ref.csv")
    dp = np.linalg.norm(np.column_stack([_col(t, f"{a}_m") - _col(ref, f"{a}_m") for a in "xyz"]), axis=1)
    bound = _col(ref, "pdop") * np.sqrt(drho2)
    assert np.all(dp <= bound + 1e-3), np.max(dp - bound)
    assert np.median(dp) > 0.01  # the rounding shows (a test of the comparison itself)
    assert t.meta["reading"]["first_epoch_time_s"] == "1777630600"  # 1777629600 s + the first time, 1000 s
    assert _col(t, "time_s")[:2].tolist() == [1777630600.0, 1777630601.0]
