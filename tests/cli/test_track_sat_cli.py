"""`motionsig track-sat`: tables beside the printed values, curves, Monte Carlo, conventions and bad input
(each bad value is one line naming the option)."""

import csv
import json
import math
from pathlib import Path

import numpy as np
import pymap3d
import pytest

from tests.cli.helpers import checkpoint_resume, engine_outputs, one_line_error, run, table, task_count


def test_table_4_3_both_conventions(capsys, tmp_path):
    rc, out, err = run(capsys, "track-sat", "table")
    assert rc == 0 and "report: 6/6 rows within 2 %" in err
    t = table(out, tmp_path)
    conv = t.column("convention")
    assert conv.count("report") == 6 and conv.count("corrected") == 6
    rep = [i for i, c in enumerate(conv) if c == "report"]
    for col in ("deviation_e0_pct", "deviation_eN_pct", "deviation_eN1_pct"):
        assert np.all(np.abs(t.numeric(col)[rep]) <= 2.0)
    assert t.meta["constants"]["corrected I"].startswith("Table 4.1 geometry at 42164.2 km")
    # corrected at the geosynchronous radius, Ex II sigma0 = 5: 825 / 195 / 252 ft (our reference values)
    i = next(k for k, (c, e, s) in enumerate(zip(conv, t.column("example"), t.numeric("sigma0_ns"), strict=True))
         if c == "corrected" and e == "II" and s == 5)  # fmt: skip
    np.testing.assert_allclose(
        [t.numeric(c)[i] for c in ("e0_ft", "eN_ft", "eN1_ft")], [825, 195, 252], atol=1
    )


def test_table_4_3_params_table_reproduces_the_corrected_column(capsys, tmp_path):
    _rc, out, _ = run(capsys, "track-sat", "table", "--convention", "corrected", "--params", "table", "-q")
    t = table(out, tmp_path)
    np.testing.assert_allclose(
        t.numeric("eN1_ft"), [171, 252, 887, 264, 460, 1198], atol=1.5
    )  # our corrected column


def test_table_4_2(capsys, tmp_path):
    rc, out, err = run(capsys, "track-sat", "table", "--which", "4.2", "-f", "json")
    assert rc == 0 and "10/10 values agree" in err
    doc = json.loads(out)
    rows = {(r["example"], r["quantity"]): r for r in doc["data"]}
    assert rows[("I", "b_123")]["report"] == pytest.approx(5.755, abs=1e-3)
    assert rows[("I", "b_123")]["corrected_at_report_radius"] == pytest.approx(1.356, abs=1e-3)
    assert doc["meta"]["fitted_radius_earth_radii"] == pytest.approx(9.235, abs=1e-3)


def test_constellation_views(capsys, tmp_path):
    rc, out, err = run(capsys, "track-sat", "constellation", "--example", "I")
    assert rc == 0 and "outside the 45 deg cone" in err  # satellite 1 at 47.2 deg at geosynchronous radius
    t = table(out, tmp_path)
    assert t.column("subset") == ["all", "1,2,3"] and t.column("gdop")[1] == ""
    rc, out, _ = run(capsys, "track-sat", "constellation", "--view", "satellites", "--rsat-re", "9.235", "-q")
    z = table(out, tmp_path).numeric("zenith_deg")
    np.testing.assert_allclose(
        z, [45.2, 20.8, 18.0, 7.1, 11.9, 30.9, 31.5], atol=0.06
    )  # zenith angles at 9.235 R_E


def test_rms_figure_preset_and_plot(capsys, tmp_path):
    png = tmp_path / "f.png"
    rc, out, _err = run(
        capsys, "track-sat", "rms", "--figure", "4.3", "--convention", "report", "--plot", str(png)
    )
    assert rc == 0 and png.stat().st_size > 10_000
    t = table(out, tmp_path)
    assert t.meta["figure"] == "4.3" and t.meta["convention"] == "report"
    n, s0, r = t.numeric("n"), t.numeric("sigma0_ns"), t.numeric("rms_ft")
    assert r[(n == 101) & (s0 == 5)][0] == pytest.approx(682, abs=1)
    assert set(t.numeric("K", integer=True)) == {3, 8}
    assert t.column("rms_no_tracking_ft")[int(np.flatnonzero(n == 101)[0])] == ""


def test_psi_command(capsys, tmp_path):
    _rc, out, _ = run(capsys, "track-sat", "psi", "--alpha", "1e-5,0.1,10", "-q")
    t = table(out, tmp_path)
    np.testing.assert_allclose(
        t.numeric("psi"), [0.04016, 0.62984, 0.98581], atol=1e-5
    )  # exact roots of the cubic


def test_simulate_small_run_and_seed_reproducibility(capsys, tmp_path):
    args = ("track-sat", "simulate", "--runs", "40", "--epochs", "30", "--outage-start", "20",
            "--outage-length", "10", "--seed", "7", "-q")  # fmt: skip
    rc, out1, _ = run(capsys, *args)
    rc2, out2, _ = run(capsys, *args)
    assert rc == rc2 == 0 and out1 == out2
    t = table(out1, tmp_path)
    assert t.meta["runs"] == 40 and "rms_kf2_ft" in t.columns
    assert t.column("rms_none_ft")[25] == ""


def test_nearly_singular_outage_satellites_are_legal(capsys):
    """The bad values of track-sat are in tests/cli/test_bad_input.py; this geometry is nearly singular but legal."""
    assert run(capsys, "track-sat", "constellation", "--outage-sats", "6,7,1")[0] == 0


@pytest.mark.parametrize(
    ("text", "needles"),
    [
        ("latitude_deg,longitude_deg\n10,100\n95,110\n30,120\n40,130\n", ("{f}:3", "latitude 95")),
        ("latitude_deg,longitude_deg\n10,100\n20,110\n", ("at least three",)),
        # duplicates and labels
        (
            "satellite,latitude_deg,longitude_deg\nA,30,100\nB,40,120\nC,30,100\nD,50,140\n",
            ("{f}:4", "line 2"),
        ),
        ("satellite,latitude_deg,longitude_deg\nA,30,100\nB,40,120\nA,35,110\nD,50,140\n", ("distinct",)),
    ],
)
def test_user_satellite_file_errors_name_file_and_line(capsys, tmp_path, text, needles):
    f = tmp_path / "sats.csv"
    f.write_text(text)
    rc, _, err = run(capsys, "track-sat", "constellation", "--sats", str(f))
    assert rc == 2 and all(n.format(f=f) in err for n in needles), err


def test_ring_constellation_reports_infinite_gdop(capsys, tmp_path):
    """Four sub-satellite points 20° (great circle) from the aircraft at four azimuths: every satellite
    has the same zenith angle, so the ones vector lies in span(U), β = 0 and the GDOP is infinite."""
    lat1, lon1, d = np.radians(45.0), np.radians(120.0), np.radians(20.0)
    rows = []
    for az in np.radians([0.0, 90.0, 180.0, 270.0]):
        lat2 = np.arcsin(np.sin(lat1) * np.cos(d) + np.cos(lat1) * np.sin(d) * np.cos(az))
        lon2 = lon1 + np.arctan2(
            np.sin(az) * np.sin(d) * np.cos(lat1), np.cos(d) - np.sin(lat1) * np.sin(lat2)
        )
        rows.append(f"{float(np.degrees(lat2))!r},{float(np.degrees(lon2))!r}")
    f = tmp_path / "ring.csv"
    f.write_text("latitude_deg,longitude_deg\n" + "\n".join(rows) + "\n")
    rc, _, err = run(capsys, "track-sat", "constellation", "--sats", str(f))
    assert rc == 2 and "GDOP is infinite" in err and "span" in err and err.count("\n") == 1


def test_output_file_is_atomic_on_error(capsys, tmp_path):
    out = tmp_path / "o.csv"
    rc, _, _ = run(capsys, "track-sat", "rms", "--epochs", "10", "-o", str(out))
    assert rc == 2 and not out.exists()


def test_rho_below_one_with_a_perfect_clock_runs(capsys, tmp_path):
    rc, out, err = run(capsys, "track-sat", "simulate", "--rho", "0.9", "--sigma0", "0", "--runs", "3",
                       "--epochs", "12", "--outage-start", "6", "--outage-length", "4", "-q")  # fmt: skip
    assert rc == 0 and err == ""
    assert (
        table(out, tmp_path).meta["max_abs_z_report_vs_analytic"] is None
    )  # the analytic column assumes rho = 1


# --- the Monte Carlo engine: --workers, --scheduler, --checkpoint ------------------------------------------

SIM = ("track-sat", "simulate", "--epochs", "20", "--outage-start", "10", "--outage-length", "5")


@pytest.mark.parametrize(
    "extra",
    [
        ("--runs", "300", "--seed", "3"),
        ("--runs", "500", "--seed", "4", "--rho", "0.9", "--sigma0", "20", "--gain", "steady",
         "--velocity-enu", "100,50,0", "--estimators", "report,kf2", "--reinit-after-outage", "--example", "II"),
        # a rho < 1 clock over 250 updates: LAPACK's Cholesky factor depends on the BLAS thread count
        # (Dask workers run single-threaded), so it is computed once and shipped with the tasks
        ("--runs", "500", "--epochs", "250", "--outage-start", "200", "--outage-length", "20", "--rho", "0.9",
         "--estimators", "report,kf2"),
    ],
    ids=["default", "rho-steady-moving", "rho-long"],
)  # fmt: skip
def test_simulate_byte_identical_for_1_2_workers_and_dask(capsys, tmp_path, dask_address, many_tasks, extra):
    outs = engine_outputs(capsys, tmp_path, dask_address, *SIM, *extra)
    assert outs["w1"] == outs["w2"] == outs["dask"]
    text = outs["w1"].decode()
    assert "workers" not in text and "scheduler" not in text and "checkpoint" not in text
    assert task_count(tmp_path, capsys, *SIM, *extra) >= 2


def test_simulate_checkpoint_resumes_to_the_uninterrupted_result(capsys, tmp_path, many_tasks):
    sim = (*SIM, "--runs", "300")
    # an interrupted run: every other task is missing
    ckpt, n_tasks = checkpoint_resume(capsys, tmp_path, sim, slice(None, None, 2))
    assert n_tasks >= 2
    err = one_line_error(capsys, *sim, "--seed", "99", "--workers", "1", "--checkpoint", str(ckpt), "-q")
    assert "--checkpoint" in err and "seed" in err


# --- any receiver geometry: --receivers (ATC-10 §4 on a user's ground stations or satellites) ----------------
#
# The receivers tables below are written by the tests themselves (csv, numpy; geodetic conversions by
# pymap3d), never by motionsig. Monte Carlo tolerances: the report tracker's RMS against the analytic recursion
# is a z-score with the delta-method standard error; under the right model each |z| is about N(0, 1), and a
# fixed seed makes every run reproducible, so "all |z| < 4" over ~60 correlated updates fails by chance with
# probability below 60 x 6.3e-5 ~ 0.4 % for a new seed, never for these. A negative control (the noise
# power doubled) shows that the comparison can fail.

TABLE_4_1 = Path(__file__).resolve().parents[2] / "data" / "atc10_table4_1.csv"
AIRPORT = (48.3538, 11.7861, 453.0)  # a reference point [deg, deg, m above WGS-84]
AIRCRAFT = "48.3538,11.7861,3.45"  # 3 km above it [km]


def _table_4_1_rows(example: str) -> list[dict[str, str]]:
    """Table 4.1 as printed (the project's data file, read with the csv module: the digits as written)."""
    with TABLE_4_1.open() as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return [r for r in rows if r["example"] == example]


def _num(t, column: str) -> np.ndarray:
    """A column of floats, blank cells (no value: e.g. no least-squares fix in an outage) as NaN."""
    return np.array([float(v) if v != "" else np.nan for v in t.column(column)])


def _data(text: str) -> list[str]:
    return [line for line in text.splitlines() if not line.startswith("#")]


def _airport_file(path, absent: dict[int, tuple[int, int]] | None = None, epochs: int = 0) -> None:
    """Five ground stations around an airport (east, north [km], height [m] above the reference point),
    written as WGS-84 latitude, longitude, altitude by pymap3d; with ``epochs``, one row per station and
    epoch (an integer epoch column), station k missing for epochs in ``absent[k]`` (inclusive)."""
    enu = [(0.0, 0.0, -3.0), (8.0, 3.0, 70.0), (-6.0, 9.0, 35.0), (-4.0, -10.0, 150.0), (12.0, -7.0, -10.0)]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["epoch", "station", "latitude", "longitude", "altitude"] if epochs else
                   ["station", "latitude", "longitude", "altitude"])  # fmt: skip
        for e in range(max(epochs, 1)):
            for k, (east, north, up) in enumerate(enu):
                lo, hi = (absent or {}).get(k, (-1, -1))
                if epochs and lo <= e <= hi:
                    continue
                lat, lon, alt = pymap3d.enu2geodetic(east * 1e3, north * 1e3, up, *AIRPORT)
                w.writerow([*([e] if epochs else []), f"RX{k + 1}", repr(float(lat)), repr(float(lon)),
                            repr(float(alt))])  # fmt: skip


def test_receivers_ecef_and_geodetic_give_the_same_constants_as_an_independent_oracle(capsys, tmp_path):
    """Six receivers — four near-geosynchronous satellites and two ground stations — written by numpy
    (ECEF, numpy.savetxt) and as WGS-84 latitude, longitude, altitude (pymap3d) give the same β, tr, b and GDOP
    (1e-9 relative: the geodetic conversions agree to ~1e-9 m, the constants are smooth in the positions),
    and both equal the constants computed here from the normal equations."""
    lat = np.array([10.0, 62.0, 35.0, 48.0, 45.6, 44.3])
    lon = np.array([150.0, 112.0, 95.0, 131.0, 120.9, 119.2])
    alt = np.array([35786e3, 35786e3, 35786e3, 35786e3, 120.0, 850.0])
    xyz = np.column_stack(pymap3d.geodetic2ecef(lat, lon, alt))
    np.savetxt(tmp_path / "ecef.csv", xyz, fmt="%.17g", delimiter=",", header="x,y,z", comments="")
    # the geodetic table from the defining coordinates (pymap3d's forward conversion is exact to ~1e-9 m; its
    # inverse is not at geosynchronous heights, tens of metres off with pymap3d 3.2)
    with open(tmp_path / "geo.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["lat_deg", "lon_deg", "height [km]"])
        w.writerows([repr(float(a)), repr(float(b)), repr(float(c) / 1e3)]
                    for a, b, c in zip(lat, lon, alt, strict=True))  # fmt: skip
    out = {}
    for name in ("ecef", "geo"):
        rc, text, err = run(capsys, "track-sat", "constellation", "--receivers", str(tmp_path / f"{name}.csv"),
                            "--aircraft", "45,120,10", "-q")  # fmt: skip
        assert rc == 0, err
        out[name] = table(text, tmp_path, f"{name}_out.csv")
    keys = ("beta", "tr", "b", "gdop")
    for k in (*keys, "b_literal"):  # all receivers, then the triplet (no GDOP: β = 0)
        for row in (0, 1)[: 1 if k == "gdop" else 2]:
            got, want = float(out["geo"].column(k)[row]), float(out["ecef"].column(k)[row])
            assert got == pytest.approx(want, rel=1e-9, abs=1e-12 if k == "beta" else 0), (k, row)
    # the oracle: unit vectors from the receivers to the aircraft, normal equations
    p = np.array(pymap3d.geodetic2ecef(45.0, 120.0, 10e3))
    U = (p - xyz) / np.linalg.norm(p - xyz, axis=1)[:, None]
    N = np.linalg.inv(U.T @ U)
    one = np.ones(6)
    beta = 6.0 - one @ U @ N @ U.T @ one
    tr, b = np.trace(N), one @ U @ N @ N @ U.T @ one
    H = np.column_stack([U, one])  # position and clock: GDOP = sqrt(trace of the position block)
    gdop = math.sqrt(np.trace(np.linalg.inv(H.T @ H)[:3, :3]))
    np.testing.assert_allclose(
        [float(out["ecef"].column(k)[0]) for k in keys], [beta, tr, b, gdop], rtol=1e-9
    )
    assert (
        out["ecef"].meta["receivers_form"] == "ECEF x, y, z"
        and out["geo"].meta["receivers_units"]["altitude"] == "km"
    )


def test_example_i_as_a_receivers_file_in_the_reports_form_reproduces_the_example(capsys, tmp_path):
    """Table 4.1's Example I written as sub-satellite latitude, longitude (no altitude: the report's form, on
    the orbit radius of the convention) gives exactly the rows of --example I: constants, satellites view (in
    report units) and the RMS curves (in report units, and in SI = feet x 0.3048, ns / 1e9)."""
    f = tmp_path / "example_i.csv"
    with open(f, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["latitude", "longitude"])
        w.writerows([r["latitude_deg"], r["longitude_deg"]] for r in _table_4_1_rows("I"))
    for args in ((), ("--view", "satellites", "--units", "report"), ("--convention", "report")):
        _, ref, _ = run(capsys, "track-sat", "constellation", "--example", "I", *args, "-q")
        rc, got, err = run(capsys, "track-sat", "constellation", "--receivers", str(f), *args, "-q")
        assert rc == 0 and _data(got) == _data(ref), err
    _, ref, _ = run(capsys, "track-sat", "rms", "--example", "I", "-q")
    rc, got, err = run(capsys, "track-sat", "rms", "--receivers", str(f), "--units", "report", "-q")
    assert rc == 0 and _data(got) == _data(ref), err
    rc, si, _ = run(capsys, "track-sat", "rms", "--receivers", str(f), "-q")
    t_ft, t_si = table(ref, tmp_path, "ft.csv"), table(si, tmp_path, "si.csv")
    assert t_si.columns == ("n", "K", "sigma0_s", "rms_m", "rms_no_tracking_m", "gain", "clock_sd_s")
    np.testing.assert_allclose(t_si.numeric("rms_m"), t_ft.numeric("rms_ft") * 0.3048, rtol=1e-15)
    np.testing.assert_allclose(t_si.numeric("clock_sd_s"), t_ft.numeric("clock_sd_ns") / 1e9, rtol=1e-15)
    assert t_si.meta["receivers"] == str(f) and t_si.meta["column_units"] == "si: metres and seconds"


def test_simulate_with_ground_receivers_around_an_airport_matches_the_analytic_curve(capsys, tmp_path):
    """Five ground stations (WGS-84, pymap3d) and an aircraft 3 km above the airport: the report tracker's
    Monte Carlo RMS (2000 runs, nonlinear TOAs) equals the analytic recursion within 4 standard errors at
    every update, the least squares its e0 outside the outage; with the TOA noise power doubled the same
    comparison fails (z > 4). σ = 5 ns keeps the errors (~3 m) far inside the linear regime at ranges of
    3-15 km."""
    f = tmp_path / "airport.csv"
    _airport_file(f)
    base = ("track-sat", "simulate", "--receivers", str(f), "--aircraft", AIRCRAFT, "--sigma0", "5",
            "--runs", "2000", "--epochs", "60", "--outage-start", "40", "--outage-length", "10",
            "--seed", "11", "-q")  # fmt: skip
    rc, out, err = run(capsys, *base, "--sigma", "5")
    assert rc == 0, err
    t = table(out, tmp_path)
    assert (
        t.meta["receivers_form"] == "WGS-84 latitude, longitude, altitude" and t.meta["aircraft"][2] == 3.45
    )
    n, K = t.numeric("n"), t.numeric("K", integer=True)
    assert set(K[(n > 40) & (n <= 50)]) == {3} and set(K[(n <= 40) | (n > 50)]) == {5}
    z = (t.numeric("rms_report_m") - t.numeric("analytic_report_m")) / t.numeric("se_report_m")
    assert np.all(np.abs(z) < 4), z
    up = (n <= 40) | (n > 50)
    zl = (_num(t, "rms_none_m")[up] - _num(t, "analytic_no_tracking_m")[up]) / _num(t, "se_none_m")[up]
    assert np.all(np.abs(zl) < 4), zl
    assert t.meta["max_abs_z_report_vs_analytic"] < 4
    assert 1.0 < t.numeric("analytic_report_m")[0] < 10.0  # metres: about σ c GDOP = 1.5 m x 1.8
    rc, out2, err = run(capsys, *base, "--sigma", str(5 * math.sqrt(2)), "--estimators", "report")
    assert rc == 0, err
    wrong = table(out2, tmp_path, "wrong.csv")
    idx = [0, 1, 10, 40]
    zw = (wrong.numeric("rms_report_m")[idx] - t.numeric("analytic_report_m")[idx]) / wrong.numeric(
        "se_report_m"
    )[idx]
    assert np.all(zw > 4), zw


def test_simulate_with_receivers_that_come_and_go(capsys, tmp_path):
    """A table with an epoch column: stations RX4 and RX5 are missing at epochs 20-30, so updates 20-30 have
    three receivers (no clock measurement, as in the report's outage: no least-squares fix there); the
    recursion at each update's geometry matches the Monte Carlo within 4 standard errors."""
    f = tmp_path / "stations.csv"
    _airport_file(f, absent={3: (20, 30), 4: (20, 30)}, epochs=61)
    rc, out, err = run(capsys, "track-sat", "simulate", "--receivers", str(f), "--aircraft", AIRCRAFT,
                       "--sigma", "5", "--sigma0", "5", "--runs", "2000", "--epochs", "60",
                       "--outage-length", "0", "--seed", "12", "-q")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    n, K = t.numeric("n"), t.numeric("K", integer=True)
    gap = (n >= 20) & (n <= 30)
    assert set(K[gap]) == {3} and set(K[~gap]) == {5}
    assert all(v == "" for v, g in zip(t.column("rms_none_m"), gap, strict=True) if g)
    z = (t.numeric("rms_report_m") - t.numeric("analytic_report_m")) / t.numeric("se_report_m")
    assert np.all(np.abs(z) < 4), z
    ana = t.numeric("analytic_report_m")
    assert ana[30] > 2 * ana[19] and ana[40] < ana[30]  # the error grows without the clock, then recovers
    assert t.meta["receivers_epochs"] == 61 and "interpolated" in t.meta["receivers_motion"]


def test_simulate_with_moving_satellites_and_timestamps(capsys, tmp_path):
    """Eight satellites drifting in latitude, positions every 10 s with ISO 8601 timestamps, satellite G8 absent
    at 50-80 s: positions are interpolated to each update, G8 is used where it is listed at both neighbouring
    epochs (updates 41-89 have 7), and the Monte Carlo matches the per-update recursion (|z| < 4)."""
    rows = _table_4_1_rows("II")
    lat0 = np.array([float(r["latitude_deg"]) for r in rows])
    lon = np.array([float(r["longitude_deg"]) for r in rows])
    with open(tmp_path / "sats.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time", "satellite", "x", "y", "z"])
        for t in range(0, 130, 10):
            x, y, z = pymap3d.geodetic2ecef(
                lat0 + 2.0 * np.sin(2 * np.pi * t / 600 + np.arange(8)), lon, 35786e3
            )
            stamp = f"2026-05-01T12:{t // 60:02d}:{t % 60:02d}Z"
            w.writerows([stamp, f"G{k + 1}", repr(float(x[k])), repr(float(y[k])), repr(float(z[k]))]
                        for k in range(8) if not (k == 7 and 50 <= t <= 80))  # fmt: skip
    rc, out, err = run(capsys, "track-sat", "simulate", "--receivers", str(tmp_path / "sats.csv"), "--runs",
                       "1000", "--epochs", "120", "--outage-start", "100", "--outage-length", "10",
                       "--seed", "5", "--units", "report", "-q")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    n, K = t.numeric("n"), t.numeric("K", integer=True)
    assert set(K[(n >= 41) & (n <= 89)]) == {7} and set(K[(n > 100) & (n <= 110)]) == {3}
    assert set(K[(n <= 40) | ((n >= 90) & (n <= 100)) | (n > 110)]) == {8}
    z = (t.numeric("rms_report_ft") - t.numeric("analytic_report_ft")) / t.numeric("se_report_ft")
    assert np.all(np.abs(z) < 4), z
    assert t.meta["receivers_time_origin"].startswith("2026-05-01T12:00:00")


GOOD_ECEF = "receiver,x,y,z\n" + "\n".join(
    f"S{k},{float(x)!r},{float(y)!r},{float(z)!r}"
    for k, (x, y, z) in enumerate(np.column_stack(pymap3d.geodetic2ecef(
        np.array([10.0, 62.0, 35.0, 48.0, 52.0]), np.array([150.0, 112.0, 95.0, 131.0, 100.0]), 35786e3)))
)  # fmt: skip
_ROWS = GOOD_ECEF.splitlines()


@pytest.mark.parametrize(
    ("command", "text", "needles"),
    [
        # coincident receivers: the later line, naming both
        ("constellation", "\n".join([*_ROWS, _ROWS[2].replace("S1", "S9")]) + "\n",
         ("{f}:7: column 'x'", "'S1' (line 3)", "coincide")),
        # fewer than three: a table of one epoch names the file, one of several the epoch's line and column
        ("constellation", "\n".join(_ROWS[:3]) + "\n", ("{f}: 2 receiver(s)", "at least 3")),
        ("simulate", "epoch," + _ROWS[0] + "\n" + "\n".join(f"0,{r}" for r in _ROWS[1:]) + "\n1," + _ROWS[1]
         + "\n1," + _ROWS[2] + "\n", ("{f}:7: column 'epoch'", "2 receiver(s) at epoch 1")),
        # three: no snapshot fix
        ("rms", "\n".join(_ROWS[:4]) + "\n", ("{f}: 3 receivers", "at least 4")),
        # kilometres in a metre column (the reader's plausibility check)
        ("constellation", "receiver,x,y,z\nA,6378.137,0,0\nB,0,6378.137,0\nC,0,0,6356.752\nD,4510,4510,0\n",
         ("{f}:2: column 'x'", "look like kilometres")),
        ("simulate", "receiver,x,y,z\n" + "\n".join(  # the same satellites in km
            ",".join([r.split(",")[0], *(repr(float(v) / 1e3) for v in r.split(",")[1:])]) for r in _ROWS[1:]) + "\n",
         ("{f}:2: column 'x'", "look like kilometres", "--units x=km")),
        # several epochs where one geometry is analysed
        ("constellation", "epoch," + _ROWS[0] + "\n" + "\n".join(f"{e},{r}" for e in (0, 1) for r in _ROWS[1:]) + "\n",
         ("{f}:7: column 'epoch'", "a second epoch", "one geometry")),
        ("rms", "time," + _ROWS[0] + "\n" + "\n".join(f"{e},{r}" for e in (0, 5) for r in _ROWS[1:]) + "\n",
         ("{f}:7: column 'time'", "a second epoch")),
        # text in a number column, a missing position column
        ("simulate", _ROWS[0] + "\n" + _ROWS[1].replace(",", ",abc,", 1).rsplit(",", 1)[0] + "\n",
         ("{f}:2: column 'x'", "'abc' is not a number")),
        ("constellation", "receiver,x,y\nA,1,2\n", ("{f}:1", "missing column 'z'")),
    ],
)  # fmt: skip
def test_bad_receivers_tables_are_one_line_naming_file_line_column(capsys, tmp_path, command, text, needles):
    f = tmp_path / "rx.csv"
    f.write_text(text)
    out = tmp_path / "o.csv"
    args = (
        ("--runs", "2", "--epochs", "4", "--outage-start", "1", "--outage-length", "1")
        if command == "simulate"
        else ()
    )
    err = one_line_error(capsys, "track-sat", command, "--receivers", str(f), *args, "-o", str(out))
    assert all(n.format(f=f) in err for n in needles), err
    assert not out.exists()


@pytest.mark.parametrize(
    ("args", "needles"),
    [
        (("constellation", "--example", "II"), ("--receivers", "--example")),
        (("constellation", "--sats", "{f}"), ("--receivers", "--sats")),
        (("rms", "--figure", "4.2"), ("--receivers", "--figure")),
        (("constellation", "--rsat-km", "50000"), ("--rsat-km/--rsat-re", "sub-satellite points")),
        (("rms", "--params", "table"), ("--params", "geometry")),
        (("constellation", "--units", "si,report"), ("--units", "both")),
        (("constellation", "--units", "x=parsec"), ("--units", "not a length unit")),
        (("constellation", "--columns", "speed=x"), ("--columns", "not a column")),
        (("constellation", "--outage-sats", "S0,S1,S9"), ("--outage-sats",)),
        (("constellation", "--aircraft", "-45,-60,0"), ("--aircraft", "line of sight")),  # the far side
        (("simulate", "--outage-sats", "S0,S1,S1", "--runs", "2"), ("--outage-sats", "distinct")),
    ],
)
def test_bad_receivers_options_are_one_line_naming_the_option(capsys, tmp_path, args, needles):
    f = tmp_path / "rx.csv"
    f.write_text(GOOD_ECEF + "\n")
    err = one_line_error(
        capsys, "track-sat", args[0], "--receivers", str(f), *(a.format(f=f) for a in args[1:])
    )
    assert all(n in err for n in needles), err


@pytest.mark.parametrize(
    ("args", "option"),
    [(("constellation", "--units", "x=km"), "--units"), (("simulate", "--columns", "x=east"), "--columns"),
     (("rms", "--aircraft", "40,100", "--convention", "report"), "--aircraft"),
     (("table", "--units", "feet"), "--units")],
)  # fmt: skip
def test_receiver_options_without_receivers_are_refused(capsys, args, option):
    assert option in one_line_error(capsys, "track-sat", *args)


def test_units_si_everywhere(capsys, tmp_path):
    """--units si: Table 4.3 in metres and seconds (the printed values converted too), the satellites view's
    ranges in metres, ψ unchanged (dimensionless); the default stays the report's feet and ns."""
    _, ft, _ = run(capsys, "track-sat", "table", "-q")
    _, si, _ = run(capsys, "track-sat", "table", "--units", "si", "-q")
    a, b = table(ft, tmp_path, "a.csv"), table(si, tmp_path, "b.csv")
    for c in ("e0", "printed_e0", "eN", "eN1"):
        np.testing.assert_allclose(b.numeric(f"{c}_m"), a.numeric(f"{c}_ft") * 0.3048, rtol=1e-15)
    np.testing.assert_array_equal(b.numeric("sigma0_s"), a.numeric("sigma0_ns") / 1e9)
    np.testing.assert_array_equal(b.numeric("deviation_eN_pct"), a.numeric("deviation_eN_pct"))
    assert _data(run(capsys, "track-sat", "psi", "--units", "si", "-q")[1]) == _data(
        run(capsys, "track-sat", "psi", "-q")[1]
    )
    _, km, _ = run(capsys, "track-sat", "constellation", "--view", "satellites", "-q")
    _, m, _ = run(capsys, "track-sat", "constellation", "--view", "satellites", "--units", "si", "-q")
    np.testing.assert_allclose(table(m, tmp_path, "m.csv").numeric("range_m"),
                               table(km, tmp_path, "k.csv").numeric("range_km") * 1e3, rtol=1e-15)  # fmt: skip


def test_ground_receivers_view_and_rms(capsys, tmp_path):
    """The receivers view in SI (positions, geodetic coordinates as read, zenith angles beyond 90° for ground
    stations below the aircraft) and the RMS curves of a ground network with an outage triplet named by label."""
    f = tmp_path / "airport.csv"
    _airport_file(f)
    rc, out, err = run(capsys, "track-sat", "constellation", "--receivers", str(f), "--aircraft", AIRCRAFT,
                       "--view", "satellites", "--outage-sats", "RX2,RX3,RX4", "-q")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.columns[:4] == ("receiver", "x_m", "y_m", "z_m") and t.column("receiver")[0] == "RX1"
    assert np.all(t.numeric("zenith_deg")[1:] > 90) and t.numeric("zenith_deg")[0] == pytest.approx(
        180, abs=1e-6
    )
    assert t.column("outage_triplet") == ["false", "true", "true", "true", "false"]
    np.testing.assert_allclose(t.numeric("range_m")[0], 3450 - 450, atol=1e-6)  # straight down to RX1
    rc, out, err = run(capsys, "track-sat", "rms", "--receivers", str(f), "--aircraft", AIRCRAFT, "--sigma", "5",
                       "--outage-sats", "RX2,RX3,RX4", "--units", "report", "-q")  # fmt: skip
    assert rc == 0, err
    r = table(out, tmp_path, "r.csv")
    assert r.meta["outage"]["satellites"] == "RX2,RX3,RX4" and set(r.numeric("K", integer=True)) == {3, 5}
    assert "rms_ft" in r.columns and r.meta["column_units"].startswith("report")


def test_simulate_with_receivers_is_byte_identical_for_1_2_workers_and_dask(
    capsys, tmp_path, dask_address, many_tasks
):
    """Receivers that come and go (an epoch column): the same bytes from 1 and 2 local workers and a Dask
    cluster, split into several tasks."""
    f = tmp_path / "stations.csv"
    _airport_file(f, absent={4: (5, 8)}, epochs=21)
    args = ("track-sat", "simulate", "--receivers", str(f), "--aircraft", AIRCRAFT, "--sigma", "5",
            "--sigma0", "5", "--runs", "300", "--epochs", "20", "--outage-start", "12", "--outage-length", "4",
            "--seed", "9")  # fmt: skip
    outs = engine_outputs(capsys, tmp_path, dask_address, *args)
    assert outs["w1"] == outs["w2"] == outs["dask"]
    assert task_count(tmp_path, capsys, *args) >= 2
