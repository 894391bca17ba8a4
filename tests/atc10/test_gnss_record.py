"""``track-sat solve`` on real GPS pseudoranges (tests/data/gnss: 6 epochs, 7 GPS L1 satellites, a phone
standing still; its ground truth): every epoch solved within metres of the truth with the Earth-rotation
correction, a satellite missing from some epochs, a +3 km fault excluded and named, an epoch with three
satellites without a fix while the others solve, pseudoranges in km without a unit refused."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from motionsig_cli.geodesy import geodetic_to_ecef
from motionsig_cli.surveillance.earth_rotation import rotate_for_flight
from tests.cli.helpers import one_line_error, run, table

DATA = Path(__file__).resolve().parents[1] / "data" / "gnss"
RECORD = DATA / "gsdc2022_mtv.csv"


def _rows() -> tuple[list[str], list[list[str]]]:
    rows = list(csv.reader(open(RECORD, newline="")))
    return rows[0], rows[1:]


def _truth() -> np.ndarray:
    t = list(csv.DictReader(open(DATA / "gsdc2022_mtv_truth.csv", newline="")))
    return np.array(
        [geodetic_to_ecef(float(r["latitude"]), float(r["longitude"]), float(r["altitude"])) for r in t]
    )


def _write(tmp_path: Path, keep=lambda r: True, change=lambda r: r) -> Path:
    head, body = _rows()
    p = tmp_path / "gps.csv"
    with open(p, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(head)
        for r in body:
            if keep(r):
                w.writerow(change(list(r)))
    return p


def _solve(capsys, tmp_path, path, *extra):
    rc, out, err = run(capsys, "track-sat", "solve", str(path), *extra)
    assert rc == 0, err
    t = table(out, tmp_path)
    rows = [dict(zip(t.columns, r, strict=True)) for r in t.rows]
    pos = np.array(
        [[np.nan if r[a] in (None, "") else float(r[a]) for a in ("x_m", "y_m", "z_m")] for r in rows]
    )
    return t, rows, pos, err


def _wls(S, rho, sig, rotate):
    """An independent weighted least squares (plain Gauss-Newton, numpy lstsq), from the Earth's centre."""
    x = np.zeros(4)
    for _ in range(30):
        Sr = rotate_for_flight(S[None], x[None, :3])[0] if rotate else S
        d = x[:3] - Sr
        r = np.linalg.norm(d, axis=1)
        H = np.c_[d / r[:, None], np.ones(len(r))]
        x = x + np.linalg.lstsq(H / sig[:, None], (rho - r - x[3]) / sig, rcond=None)[0]
    return x


def test_every_epoch_is_solved_within_metres_of_the_truth_and_equals_an_independent_wls(capsys, tmp_path):
    truth = _truth()
    t, rows, pos, _ = _solve(capsys, tmp_path, RECORD, "--earth-rotation")
    err = np.linalg.norm(pos - truth, axis=1)
    assert all(r["status"] == "fix" and r["excluded"] in (None, "") for r in rows)
    assert err.max() < 8.0, err  # measured 2.1 to 6.4 m
    _, _, plain, _ = _solve(capsys, tmp_path, RECORD)
    err_plain = np.linalg.norm(plain - truth, axis=1)
    assert err_plain.min() > 15.0 and np.median(err_plain - err) > 15.0, err_plain  # measured 22 to 28 m
    _, body = _rows()
    for e in range(6):
        sel = [r for r in body if r[0] == str(e)]
        S = np.array([[float(v) for v in r[3:6]] for r in sel])
        rho = np.array([float(r[6]) for r in sel])
        sig = np.array([float(r[7]) for r in sel])
        for rotate, got in ((True, pos[e]), (False, plain[e])):
            x = _wls(S, rho, sig, rotate)
            assert np.linalg.norm(got - x[:3]) < 1e-6
    assert (
        t.meta["fault_exclusion"]["epochs_tested"] == 6
        and t.meta["fault_exclusion"]["receivers_excluded"] == 0
    )


def test_a_missing_satellite_a_fault_and_a_three_satellite_epoch(capsys, tmp_path):
    truth = _truth()

    def keep(r):
        if r[0] in ("1", "3") and r[2] == "G25":  # a satellite absent from some epochs
            return False
        return not (r[0] == "4" and r[2] in ("G02", "G05", "G06", "G12"))  # three satellites left

    def change(r):
        if r[0] == "2" and r[2] == "G19":
            r[6] = f"{float(r[6]) + 3000.0:.6f}"  # +3 km
        return r

    t, rows, pos, err = _solve(capsys, tmp_path, _write(tmp_path, keep, change), "--earth-rotation")
    assert [int(r["n_receivers"]) for r in rows] == [7, 6, 7, 6, 3, 7]
    assert [r["status"] for r in rows] == ["fix"] * 4 + ["no fix: 3 receiver(s), a fix needs 4", "fix"]
    assert rows[2]["excluded"] == "G19" and all(
        r["excluded"] in (None, "") for i, r in enumerate(rows) if i != 2
    )
    assert float(rows[2]["test_statistic"]) < float(rows[2]["test_threshold"]) and rows[2]["integrity"] in (
        True,
        "true",
    )
    e = np.linalg.norm(pos - truth, axis=1)
    assert np.isnan(e[4]) and np.nanmax(e) < 10.0, e
    fe = t.meta["fault_exclusion"]
    assert (
        fe["receivers_excluded"] == 1
        and fe["excluded_by_receiver"] == {"G19": 1}
        and fe["epochs_alarmed"] == 1
    )
    assert t.meta["fixes"]["no_fix"] == {"too few receivers": 1}
    assert "1 measurement(s) excluded as faulty in 1 epoch(s)" in err
    # without the exclusion the fault pulls the fix hundreds of metres away, and the test says so
    _, rows_off, pos_off, _ = _solve(
        capsys, tmp_path, _write(tmp_path, keep, change), "--earth-rotation", "--no-fde"
    )
    assert np.linalg.norm(pos_off[2] - truth[2]) > 100.0 and float(rows_off[2]["test_statistic"]) > float(
        rows_off[2]["test_threshold"]
    )


def test_pseudoranges_in_km_without_a_unit_are_refused(capsys, tmp_path):
    def km(r):
        r[6], r[7] = f"{float(r[6]) / 1000:.9f}", f"{float(r[7]) / 1000:.9f}"
        return r

    p = _write(tmp_path, change=km)
    err = one_line_error(capsys, "track-sat", "solve", str(p))
    assert (
        "gps.csv:2: column 'pseudorange': the pseudorange values do not fit the receivers' positions" in err
    )
    assert "km below the WGS-84 ellipsoid" in err and "they fit as kilometres" in err, err
    rc, _, err2 = run(capsys, "track-sat", "solve", str(p), "--units", "pseudorange=km,sigma=km", "-q")
    assert rc == 0, err2


@pytest.mark.parametrize(("sigma", "metres"), [("5", 5.0), ("5m", 5.0), ("500cm", 5.0), ("10ns", 2.99792458)])
def test_sigma_is_in_the_measurement_unit_or_carries_one(capsys, tmp_path, sigma, metres):
    t, _, _, _ = _solve(capsys, tmp_path, RECORD, "--sigma", sigma, "-q")
    assert t.meta["sigma"].startswith("--sigma") and f"({metres:.6g} m of range)" in t.meta["sigma"]


def test_a_plain_sigma_for_times_is_seconds(capsys, tmp_path):
    p = tmp_path / "toa.csv"
    p.write_text("epoch,receiver,toa,x,y,z\n0,A,0.001,0,0,6378137\n")
    err = one_line_error(capsys, "track-sat", "solve", str(p), "--sigma", "10")
    assert "--sigma" in err and "10 ns is 10ns" in err, err


def test_the_fixes_equal_gnss_lib_py_weighted_least_squares():
    """gnss_lib_py's solve_wls on the same pseudoranges, satellite positions and weights 1/σ²: with the
    positions taken as given (sv_rx_time=True) the fixes agree to 1e-8 m; with its Earth-rotation
    correction (sv_rx_time=False) against --earth-rotation to 3e-6 m (measured; the two iterate the
    flight time differently)."""
    import warnings

    snapshot = pytest.importorskip("gnss_lib_py.algorithms.snapshot")
    NavData = pytest.importorskip("gnss_lib_py.navdata.navdata").NavData
    from motionsig_cli.atc10 import toa_solve as ts

    rows = list(csv.DictReader(open(RECORD, newline="")))
    nd = NavData()
    nd["gps_millis"] = np.array([float(r["epoch"]) * 1000 for r in rows])
    for a in "xyz":
        nd[f"{a}_sv_m"] = np.array([float(r[a]) for r in rows])
    nd["corr_pr_m"] = np.array([float(r["pseudorange"]) for r in rows])
    nd["weight"] = np.array([1 / float(r["sigma"]) ** 2 for r in rows])
    meas = ts.read_measurements(RECORD)
    for rx_time, rotate, tol in ((True, False, 1e-6), (False, True, 1e-4)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ref = snapshot.solve_wls(nd, weight_type="weight", sv_rx_time=rx_time, tol=1e-9, max_count=100)
        xyz = np.stack([ref["x_rx_wls_m"], ref["y_rx_wls_m"], ref["z_rx_wls_m"]], axis=-1)
        res = ts.solve(meas, ts.SolveConfig(earth_rotation=rotate))
        np.testing.assert_allclose(res.fix.position, xyz, rtol=0, atol=tol)
        np.testing.assert_allclose(res.fix.bias, ref["b_rx_wls_m"], rtol=0, atol=tol)


def test_without_sigma_one_bad_epoch_does_not_inflate_the_others(capsys, tmp_path):
    """No sigma column: unit weights, no fault test, and each epoch's covariance scaled by its own variance
    factor, so a +3 km fault at epoch 2 leaves the other epochs' standard deviations as they were (pooling
    across epochs, when asked, spreads it over all of them)."""

    def nosig(r):
        return r[:7] + r[8:]

    def fault(r):
        r = nosig(r)
        if r[0] == "2" and r[2] == "G19":
            r[6] = f"{float(r[6]) + 3000.0:.6f}"
        return r

    head, _ = _rows()
    clean_p, bad_p = tmp_path / "clean.csv", tmp_path / "bad.csv"
    for p, ch in ((clean_p, nosig), (bad_p, fault)):
        body = [ch(list(r)) for r in _rows()[1]]
        p.write_text("\n".join(",".join(r) for r in [nosig(list(head)), *body]) + "\n")
    t, clean, _, _ = _solve(capsys, tmp_path, clean_p, "--earth-rotation")
    _, bad, _, _ = _solve(capsys, tmp_path, bad_p, "--earth-rotation")
    _, pooled, _, _ = _solve(capsys, tmp_path, bad_p, "--earth-rotation", "--covariance", "pooled")
    assert t.meta["fault_exclusion"].startswith("off") and all(r["integrity"] in (None, "") for r in bad)
    sd = lambda rows: np.array([float(r["sd_up_m"]) for r in rows])  # noqa: E731
    others = [0, 1, 3, 4, 5]
    np.testing.assert_allclose(sd(bad)[others], sd(clean)[others], rtol=1e-6)
    assert sd(bad)[2] > 10 * sd(clean)[2]
    assert np.all(sd(pooled)[others] > 5 * sd(clean)[others])
