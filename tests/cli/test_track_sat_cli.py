"""`motionsig track-sat`: tables beside the printed values, curves, Monte Carlo, conventions and bad input
(each bad value is one line naming the option)."""

import json

import numpy as np
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
