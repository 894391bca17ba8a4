"""``track-sat solve``'s computation: the report's clock tracker against its analytic error recursion (Monte
Carlo), records written here (csv module, numpy, pymap3d: not by the commands) read in their several forms,
and bad records refused with file, line and column."""

import csv
import json
import math
from decimal import Decimal

import numpy as np
import pymap3d
import pytest

from motionsig_cli.atc10 import toa_solve as ts
from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError
from motionsig_cli.surveillance.clock_tracking import ReportClock, clock_error_recursion
from motionsig_cli.surveillance.toa_fix import (
    position_covariance,
    solve_snapshot,
    weighted_pseudo_measurement,
)

C = 299_792_458.0
ORIGIN = (48.3538, 11.7861, 453.0)
ENU = np.array([[0, 0, 0], [15e3, 2e3, 30], [-12e3, 8e3, -20], [3e3, -14e3, 60], [-6e3, -9e3, 10]], float)
"""Five ground receivers around an airport (east, north, up [m] about ORIGIN)."""
SIG_NS = np.array([8.0, 10.0, 12.0, 10.0, 15.0])
"""TOA error of each receiver [ns] (unequal: the weights matter)."""


def _ecef(enu):
    enu = np.atleast_2d(enu)
    return np.stack(pymap3d.enu2ecef(enu[:, 0], enu[:, 1], enu[:, 2], *ORIGIN), axis=-1)


def _scenario(R, *, E=80, outage=(50, 60), sigma0_ns=20.0, noise_scale=1.0, seed=1):
    """R runs of a transmitter climbing across the network with a drifting clock (σ0 per 1 s epoch):
    b_n = b_0 + Σ w_i + n a_0 (eq 4.3.1, drawn here with numpy), Gaussian TOA noise; receivers 4 and 5
    miss epochs ``outage`` (three receivers: the report's outage case)."""
    rng = np.random.default_rng(seed)
    S = _ecef(ENU)
    K = len(S)
    truth = _ecef(
        np.column_stack([np.linspace(-15e3, 15e3, E), np.linspace(5e3, -5e3, E), np.linspace(3e3, 5e3, E)])
    )
    sig = SIG_NS * 1e-9 * C
    used = np.ones((E, K), bool)
    used[outage[0] : outage[1], 3:] = False
    s0 = sigma0_ns * 1e-9 * C
    w = rng.standard_normal((R, E)) * s0
    w[:, 0] = 0.0
    a0 = rng.standard_normal(R) * s0
    b = rng.uniform(-3e4, 3e4, R)[:, None] + np.cumsum(w, axis=1) + np.arange(E) * a0[:, None]
    rho = np.linalg.norm(truth[:, None] - S, axis=-1)[None] + b[:, :, None]
    rho = rho + rng.standard_normal((R, E, K)) * sig * noise_scale
    return {
        "S": S,
        "truth": truth,
        "sig": sig,
        "used": used,
        "b": b,
        "rho": np.where(used, rho, np.nan),
        "s0": s0,
    }


def _track(sc):
    """Snapshot fixes of every run and epoch with four receivers (one call), then the tracker (one call)."""
    rho, used, S = sc["rho"], sc["used"], sc["S"]
    R, E, K = rho.shape
    fe = np.flatnonzero(used.sum(axis=1) >= 4)
    r4 = rho[:, fe].reshape(-1, K)
    fix = solve_snapshot(r4, S, sigma=np.broadcast_to(sc["sig"], r4.shape))
    start = np.full((R, E, 3), np.nan)
    start[:, fe] = fix.position.reshape(R, len(fe), 3)
    weight = np.where(used, 1.0 / sc["sig"], 0.0)
    return ts.track_clock(np.where(used, rho, 0.0), np.broadcast_to(S, (E, K, 3)), weight, np.arange(E), start,
                          sigma0_m=sc["s0"])  # fmt: skip


def _analytic(sc):
    """V_n of the report's recursion (clock_tracking.clock_error_recursion) with each epoch's β̃ at the true
    position, and the position's mean-square error tr(ŨᵀŨ)⁻¹ + V_n ‖v‖² (eq 4.5.35, corrected)."""
    used, S = sc["used"], sc["S"]
    E, K = used.shape
    weight = np.where(used, 1.0 / sc["sig"], 0.0)
    pm = weighted_pseudo_measurement(np.zeros((E, K)), np.broadcast_to(S, (E, K, 3)), weight, sc["truth"])
    rec = clock_error_recursion(1.0, sc["s0"], pm.beta, used.sum(axis=1) >= 4)
    return rec.V, np.trace(position_covariance(pm, rec.V), axis1=1, axis2=2)


def _z(e2, expected):
    """(RMS − expected RMS)/SE over runs, SE by the delta method sd(e²)/(2 RMS √R) (as track-sat simulate)."""
    rms = np.sqrt(e2.mean(axis=0))
    se = e2.std(axis=0, ddof=1) / math.sqrt(e2.shape[0]) / (2.0 * rms)
    return (rms - np.sqrt(expected)) / se


EPOCHS = [0, 1, 5, 20, 49, 50, 55, 59, 60, 61, 79]
"""Start, convergence, steady state, the outage (50–59: three receivers) and after it."""


@pytest.fixture(scope="module")
def mc():
    sc = _scenario(1000)
    return sc, _track(sc)


def test_tracked_clock_error_matches_the_analytic_recursion(mc):
    """1000 runs: the RMS clock error of the tracker equals √V_n of the report's recursion within 4 standard
    errors at 11 epochs (start, steady state, the 3-receiver outage, after it). The recursion is exact for
    the linearised problem; the linearisation error is far below the noise (ranges of 10 km, errors of
    metres). Measured max |z| = 2.0 over all 80 epochs with 400 runs."""
    sc, tr = mc
    V, _ = _analytic(sc)
    z = _z((tr.bias - sc["b"]) ** 2, V)
    assert np.all(np.abs(z[EPOCHS]) < 4), z[EPOCHS]
    np.testing.assert_allclose(tr.var[0], V, rtol=0.02)  # the tracker's own V at its estimate ≈ the truth's
    assert tr.mode[:3] == ("init", "update", "update") and tr.mode[50:60] == ("outage",) * 10


def test_tracked_position_error_matches_the_analytic_value(mc):
    """The same for the position: E‖p̂ − p‖² = tr(ŨᵀŨ)⁻¹ + V_n ‖(ŨᵀŨ)⁻¹Ũᵀ1̃‖² (eq 4.5.35 corrected), in the
    outage with three receivers (position from the clock prediction) as well."""
    sc, tr = mc
    _, P = _analytic(sc)
    z = _z(np.sum((tr.position - sc["truth"]) ** 2, axis=-1), P)
    assert np.all(np.abs(z[EPOCHS]) < 4), z[EPOCHS]
    assert np.sqrt(P[55]) < 100.0  # the outage is bridged: tens of metres (78 m), not kilometres


def test_negative_control_wrong_noise_power_is_detected():
    """With the TOA noise √2 times what the tracker is told, the comparison fails (z > 4) wherever the
    clock is updated."""
    sc = _scenario(1000, noise_scale=math.sqrt(2), seed=2)
    tr = _track(sc)
    V, _ = _analytic(sc)
    z = _z((tr.bias - sc["b"]) ** 2, V)
    assert np.all(z[[0, 1, 5, 20, 49, 61, 79]] > 4), z


def test_closed_form_prediction_equals_repeated_predict_steps():
    a, b = ReportClock(1.0, 3.0), ReportClock(1.0, 3.0)
    for t in (a, b):
        t.reinit(np.array([5.0]), np.array([0.25]))
        t.commit(np.array([5.5]), np.array([0.25]))
    ts._advance(a, 7)
    for _ in range(7):
        b.commit(np.array([np.nan]), None)
    np.testing.assert_allclose(a.V, b.V, rtol=1e-14)
    np.testing.assert_allclose(a.chi, b.chi, rtol=1e-14)


# --- records ------------------------------------------------------------------------------------------------


def _record(
    tmp_path, sc, run=0, *, name="toa.csv", form="toa", positions=None, t0=1000.0, drop=(), iso=False
):
    """One run of a scenario as a CSV: epoch, time, receiver, toa [s] (or pseudorange [m]) and sigma [ns]
    (the TOAs share the time column's frame: toa = t_n + ρ/c); ``positions``: ``ecef`` or ``geodetic``
    columns in the record instead of a receivers file; ``drop``: (epoch, receiver) rows left out."""
    E, K = sc["used"].shape
    lat, lon, alt = pymap3d.ecef2geodetic(sc["S"][:, 0], sc["S"][:, 1], sc["S"][:, 2])
    path = tmp_path / name
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        head = ["epoch", "time", "receiver", "toa" if form == "toa" else "pseudorange [m]"]
        head.append("sigma [ns]" if form == "toa" else "sigma [m]")
        head += {"ecef": ["x", "y", "z"], "geodetic": ["lat", "lon", "alt"], None: []}[positions]
        w.writerow(head)
        for n in range(E):
            t = f"2026-05-01T12:{n // 60:02d}:{n % 60:02d}Z" if iso else repr(t0 + n)
            for k in range(K):
                if (n, k) in drop:
                    continue
                rho = float(sc["rho"][run, n, k])
                if math.isnan(rho):
                    m = ""
                elif form == "toa":
                    m = repr(rho / C) if iso else repr(t0 + n + rho / C)
                else:
                    m = repr(rho)
                row = [
                    n,
                    t,
                    f"R{k + 1}",
                    m,
                    repr(float(SIG_NS[k] if form == "toa" else SIG_NS[k] * 1e-9 * C)),
                ]
                if positions == "ecef":
                    row += [repr(float(v)) for v in sc["S"][k]]
                elif positions == "geodetic":
                    row += [repr(float(lat[k])), repr(float(lon[k])), repr(float(alt[k]))]
                w.writerow(row)
    return path


def _receivers(tmp_path, sc, name="rx.csv"):
    path = tmp_path / name
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["receiver", "x", "y", "z"])
        for k, p in enumerate(sc["S"]):
            w.writerow([f"R{k + 1}", *(repr(float(v)) for v in p)])
    return path


@pytest.fixture(scope="module")
def small():
    return _scenario(3, E=30, outage=(12, 16), seed=5)


def _columns(table, *names):
    idx = [table.columns.index(n) for n in names]
    return np.array([[np.nan if r[i] is None else r[i] for i in idx] for r in table.rows], float)


def test_a_record_gives_what_the_arrays_give(tmp_path, small):
    """A CSV record (TOAs in the time column's frame) through read_measurements and solve equals the array
    computation for the same run: snapshot fixes to 1 mm (the TOAs' text carries ~1e-13 s of rounding at
    t ≈ 1000 s, 3e-5 m), the track to 1 mm."""
    sc = small
    meas = ts.read_measurements(_record(tmp_path, sc, run=1), receivers=_receivers(tmp_path, sc))
    assert (
        meas.kind == "toa" and meas.E == 30 and meas.K == 5 and meas.labels == ("R1", "R2", "R3", "R4", "R5")
    )
    np.testing.assert_allclose(meas.sigma[0], SIG_NS * 1e-9 * C, rtol=1e-15)
    res = ts.solve(meas, ts.SolveConfig(clock="track", sigma0_ns=20.0))
    tr = _track({**sc, "rho": sc["rho"][1:2]})
    np.testing.assert_allclose(res.track.bias[0], tr.bias[0], rtol=0, atol=1e-3)
    np.testing.assert_allclose(res.track.position[0], tr.position[0], rtol=0, atol=1e-3)
    fe = np.flatnonzero(sc["used"].sum(axis=1) >= 4)
    fix = solve_snapshot(sc["rho"][1, fe], sc["S"], sigma=SIG_NS * 1e-9 * C)
    np.testing.assert_allclose(res.fix.position[fe], fix.position, rtol=0, atol=1e-3)
    np.testing.assert_allclose(res.fix.clock_offset_s[fe], fix.bias / C, rtol=0, atol=1e-11)
    assert res.track.mode[12:16] == ("outage",) * 4


def test_the_record_forms_agree(tmp_path, small):
    """Receivers file or positions in the record (ECEF or WGS-84), TOAs or pseudoranges, times in seconds
    (TOAs absolute) or ISO 8601 (TOAs from each epoch's time), empty cells or absent rows: the same fixes."""
    sc = small
    rxf = _receivers(tmp_path, sc)
    cfg = ts.SolveConfig(clock="track", sigma0_ns=20.0)
    ref = ts.solve(ts.read_measurements(_record(tmp_path, sc), receivers=rxf), cfg)
    outage = [(n, k) for n in range(12, 16) for k in (3, 4)]
    variants = {
        "ecef": ts.read_measurements(_record(tmp_path, sc, name="e.csv", positions="ecef")),
        "geodetic": ts.read_measurements(_record(tmp_path, sc, name="g.csv", positions="geodetic")),
        "pseudorange": ts.read_measurements(
            _record(tmp_path, sc, name="p.csv", form="pseudorange"), receivers=rxf
        ),
        "iso": ts.read_measurements(
            _record(tmp_path, sc, name="i.csv", iso=True), receivers=rxf, toa_origin="epoch"
        ),
        "absent rows": ts.read_measurements(_record(tmp_path, sc, name="a.csv", drop=outage), receivers=rxf),
    }
    for name, meas in variants.items():
        res = ts.solve(meas, cfg)
        np.testing.assert_allclose(res.fix.position, ref.fix.position, rtol=0, atol=1e-3, err_msg=name)
        np.testing.assert_allclose(res.track.position, ref.track.position, rtol=0, atol=1e-3, err_msg=name)
        np.testing.assert_allclose(res.track.bias, ref.track.bias, rtol=0, atol=1e-3, err_msg=name)
    assert variants["iso"].record.time_origin == "2026-05-01T12:00:00+00:00"


def test_missing_epochs_are_predicted_steps(tmp_path, small):
    """Epochs 20–22 absent from the record: the tracker predicts through them (steps from the epoch
    numbers), as track_clock with those steps does."""
    sc = small
    drop = [(n, k) for n in (20, 21, 22) for k in range(5)]
    meas = ts.read_measurements(_record(tmp_path, sc, drop=drop), receivers=_receivers(tmp_path, sc))
    assert meas.E == 27
    res = ts.solve(meas, ts.SolveConfig(clock="track", sigma0_ns=20.0))
    keep = np.array([n for n in range(30) if n not in (20, 21, 22)])
    sub = {**sc, "rho": sc["rho"][:1, keep], "used": sc["used"][keep], "truth": sc["truth"][keep]}
    _, E, K = sub["rho"].shape
    fix = solve_snapshot(sub["rho"][0][sub["used"].sum(1) >= 4], sc["S"], sigma=SIG_NS * 1e-9 * C)
    start = np.full((1, E, 3), np.nan)
    start[0, sub["used"].sum(1) >= 4] = fix.position
    tr = ts.track_clock(np.where(sub["used"], sub["rho"], 0.0), np.broadcast_to(sc["S"], (E, K, 3)),
                        np.where(sub["used"], 1 / sc["sig"], 0.0), keep, start, sigma0_m=sc["s0"])  # fmt: skip
    np.testing.assert_allclose(res.track.bias, tr.bias, rtol=0, atol=1e-3)
    assert res.steps.tolist() == keep.tolist()
    V = res.track.var[0]
    assert V[keep.tolist().index(23)] > 3 * V[keep.tolist().index(19)]  # the gap costs clock accuracy


def test_receivers_that_move_per_epoch_by_time(tmp_path, small):
    """A receivers file with a position per epoch, by ISO timestamps whose origin differs from the
    record's: each row takes its epoch's position (here the static positions repeated, shifted by 0 s)."""
    sc = small
    path = tmp_path / "moving.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "receiver", "x", "y", "z"])
        for n in range(-2, 32):  # the file starts 2 s before the record
            for k, p in enumerate(sc["S"]):
                t = (
                    f"2026-05-01T11:59:{58 + n:02d}Z"
                    if n < 2
                    else f"2026-05-01T12:{(n - 2) // 60:02d}:{(n - 2) % 60:02d}Z"
                )
                w.writerow([t, f"R{k + 1}", *(repr(float(v)) for v in p)])
    rec = _record(tmp_path, sc, iso=True)
    a = ts.read_measurements(rec, receivers=path, toa_origin="epoch")
    b = ts.read_measurements(rec, receivers=_receivers(tmp_path, sc), toa_origin="epoch")
    np.testing.assert_array_equal(a.receivers, b.receivers)


def test_report_units_and_views(tmp_path, small):
    sc = small
    meas = ts.read_measurements(_record(tmp_path, sc), receivers=_receivers(tmp_path, sc))
    si = ts.solve_report(meas, ts.SolveConfig(clock="track", sigma0_ns=20.0, full_covariance=True)).table
    rep = ts.solve_report(meas, ts.SolveConfig(clock="track", sigma0_ns=20.0, units="report")).table
    a = _columns(
        si, "x_m", "altitude_m", "clock_offset_s", "sd_up_m", "track_clock_offset_s", "rms_residual_s"
    )
    b = _columns(
        rep, "x_ft", "altitude_ft", "clock_offset_ns", "sd_up_ft", "track_clock_offset_ns", "rms_residual_ns"
    )
    np.testing.assert_allclose(b, a * [1 / 0.3048, 1 / 0.3048, 1e9, 1 / 0.3048, 1e9, 1e9], rtol=1e-12)
    cov = _columns(si, "cov_x_x_m2", "sd_x_m", "cov_clock_clock_s2", "sd_clock_offset_s")
    np.testing.assert_allclose(np.sqrt(cov[:, [0, 2]]), cov[:, [1, 3]], rtol=1e-9)
    res = ts.solve_report(meas, ts.SolveConfig(view="residuals", clock="track", sigma0_ns=20.0)).table
    assert len(res.rows) == 30 * 5 and res.columns[:5] == (
        "line",
        "epoch",
        "time_s",
        "receiver",
        "measured",
    )
    z = _columns(res, "normalised_residual")[:, 0]
    assert sum(not r[4] for r in res.rows) == 8  # the empty cells of the outage
    assert np.nanmax(np.abs(z)) < 5 and np.isnan(z).sum() == 4 * 5  # the outage epochs have no snapshot fix
    assert si.meta["track"]["modes"] == {"init": 1, "update": 25, "outage": 4}
    assert "emission time minus the epoch's nominal time" in si.meta["clock_offset"]


# --- bad records ----------------------------------------------------------------------------------------------

RX_GEO = [
    (48.35, 11.78, 450.0),
    (48.40, 11.99, 500.0),
    (48.23, 11.83, 530.0),
    (48.27, 11.70, 470.0),
    (48.46, 11.91, 466.0),
]
RX = "receiver,lat,lon,alt\n" + "".join(f"R{k + 1},{a},{b},{h}\n" for k, (a, b, h) in enumerate(RX_GEO))


def _good():
    """Three epochs of five receivers seeing a transmitter 3 km up, 1e-4 s late, exact TOAs."""
    S = np.stack(pymap3d.geodetic2ecef(*np.array(RX_GEO).T), axis=-1)
    lines = []
    for n in range(3):
        p = np.stack(pymap3d.geodetic2ecef(48.33 + 0.01 * n, 11.85, 3000.0))
        for k in range(5):
            toa = 1000.0 + n + 1e-4 + float(np.linalg.norm(p - S[k])) / C
            lines.append(f"{n},{1000 + n},R{k + 1},{toa!r},10\n")
    return "epoch,time,receiver,toa,sigma [ns]\n" + "".join(lines)


GOOD = _good()


def _bad(tmp_path, text, rx_text=RX, **kw):
    p = tmp_path / "m.csv"
    p.write_text(text)
    r = tmp_path / "r.csv"
    r.write_text(rx_text or "")
    meas = ts.read_measurements(p, receivers=r if rx_text is not None else None, **kw)
    return ts.solve(meas, kw.pop("cfg", ts.SolveConfig()))


def _lines(text, *drop, replace=None):
    rows = text.splitlines()
    for i, new in (replace or {}).items():
        rows[i - 1] = new
    return "\n".join(r for i, r in enumerate(rows, 1) if i not in drop) + "\n"


def _drop_epoch(text):
    """The record without its epoch column (the epochs are then the runs of equal times)."""
    return "\n".join(",".join(r.split(",")[1:]) for r in text.splitlines()) + "\n"


def _ns(text):
    """The record with its times in integer nanoseconds (``time [ns]``)."""
    rows = text.splitlines()
    out = [rows[0].replace(",time,", ",time [ns],")]
    for r in rows[1:]:
        c = r.split(",")
        c[1] = str(int(c[1]) * 10**9)
        out.append(",".join(c))
    return "\n".join(out) + "\n"


KM_RX = "receiver,x,y,z\n" + "".join(
    f"R{k + 1},{float(x) / 1e3!r},{float(y) / 1e3!r},{float(z) / 1e3!r}\n"
    for k, (x, y, z) in enumerate(zip(*pymap3d.geodetic2ecef(*np.array(RX_GEO).T), strict=True))
)
LINE_RX = "receiver,x,y,z\n" + "".join(
    f"R{k},{6378137.0 + 100 * k},{2000.0 * k},{1000.0 * k}\n" for k in range(1, 6)
)

BAD_RECORDS = {
    "time backwards": (_lines(GOOD, replace={7: "1,999.5,R1,1001.0001,10"}), RX,
                       r"m.csv:7: column 'time': epoch 1 has two times: 999.5 s here, 1001 s at line 8 and 3 more"),
    "time backwards without epochs": (_drop_epoch(_lines(GOOD, replace={7: "1,999.5,R1,1001.0001,10"})), RX,
                                      r"m.csv:7: column 'time': time goes backwards \(999.5 s after 1000 s\)"),
    "two times in an epoch": (_lines(GOOD, replace={11: "1,1001.5,R5,1001.0001,10"}), RX, r"m.csv:11: column 'time': epoch 1 has two times"),
    "odd time inside an epoch": (GOOD.replace(",1000,R3,", ",1000.5,R3,"), RX,  # not blamed on the row after it
                                 r"m.csv:4: column 'time': epoch 0 has two times: 1000.5 s here, 1000 s at line 2 and 3 more"),
    "ns times of an epoch differ": (_ns(GOOD).replace("0,1000000000000,R3,", "0,1000000000001,R3,"), RX,
                                    r"m.csv:4: column 'time \[ns\]': epoch 0 has two times: 1000000000001 ns here"),
    "epoch backwards": (_lines(GOOD, replace={12: "0,1002,R1,1002.0001,10"}), RX, r"m.csv:12: column 'epoch': epoch goes backwards \(0 after 1\)"),
    "text in number": (_lines(GOOD, replace={4: "0,1000,R3,abc,10"}), RX, r"m.csv:4: column 'toa': 'abc' is not a number"),
    "unknown receiver": (_lines(GOOD, replace={4: "0,1000,R9,1000.0002,10"}), RX, r"m.csv:4: column 'receiver': unknown receiver 'R9' \(.*r.csv lists R1, R2"),
    "too few everywhere": (_lines(GOOD, 3, 4, 8, 9, 13, 14), RX, r"m.csv:2: column 'toa': epoch 0 has 3 receiver\(s\) with a measurement: a snapshot fix needs at least 4 \(and no epoch"),
    "coincident": (GOOD, RX.replace("R3,48.23,11.83,530", "R3,48.40,11.99,500"), r"r.csv:4: column 'lat': receivers 'R2' \(line 3\) and 'R3' \(line 4\) coincide"),
    "km receivers": (GOOD, KM_RX, r"r.csv:2: column 'x': positions look like kilometres"),
    "singular": (GOOD, LINE_RX, r"m.csv:2: column 'receiver': epoch 0: the geometry is singular"),
    "duplicate": (_lines(GOOD, replace={3: "0,1000,R1,1000.0002,10"}), RX, r"m.csv:3: column 'receiver': receiver 'R1' appears twice at one epoch \(lines 2 and 3\)"),
    "missing column": (GOOD.replace("toa", "arrival_time"), RX, r"m.csv:1: missing column 'toa'"),
    "other frame": (GOOD.replace(",1000,", ",0,").replace(",1001,", ",1,").replace(",1002,", ",2,"), RX,
                    r"m.csv:2: column 'toa': arrival 1000.00012\d* s is 1000 s from the epoch's time 0 s"),
    "absolute toa without time": ("epoch,receiver,toa\n0,R1,1000.0001\n", RX, r"m.csv:2: column 'toa': arrival 1000.0001 s is 1000 s from the epoch's time 0 s .* --toa-origin"),
    "sigma not positive": (_lines(GOOD, replace={5: "0,1000,R4,1000.0003,0"}), RX, r"m.csv:5: column 'sigma \[ns\]': sigma 0 is not > 0"),
    "sigma missing": (_lines(GOOD, replace={5: "0,1000,R4,1000.0003,"}), RX, r"m.csv:5: column 'sigma \[ns\]': sigma missing"),
    "no receiver column": (GOOD.replace("receiver", "stn"), RX, r"m.csv:1: missing column 'receiver'"),
    # the receivers file is numbered 1..5 by row, the record names 5..1: refused, not paired by row
    "receivers without labels": (GOOD.replace(",R1,", ",5,").replace(",R2,", ",4,").replace(",R4,", ",2,")
                                 .replace(",R5,", ",1,").replace(",R3,", ",3,"),
                                 "\n".join(r.split(",", 1)[1] for r in RX.splitlines()) + "\n",
                                 r"r.csv:1: no receiver column: map one with --receivers-columns receiver=NAME "
                                 r"\(columns: lat, lon, alt"),
    "no positions": (GOOD, None, r"m.csv:1: no receiver positions"),
    "both forms": (GOOD.replace("toa,", "toa,pr,").replace(",10\n", ",1,10\n"), RX, r"m.csv:1: columns 'toa' and 'pr'"),
    "empty": ("", RX, r"m.csv: no header row"),
    "header only": ("epoch,receiver,toa\n", RX, r"m.csv: no measurements"),
    "unknown unit": (GOOD.replace("sigma [ns]", "sigma [fortnight]"), RX, r"m.csv:1: column 'sigma \[fortnight\]': unknown time unit"),
}  # fmt: skip


@pytest.mark.parametrize("name", list(BAD_RECORDS))
def test_bad_records_are_refused_with_file_line_and_column(tmp_path, name):
    text, rx_text, match = BAD_RECORDS[name]
    with pytest.raises(InputError, match=match):
        _bad(tmp_path, text, rx_text)


@pytest.mark.parametrize(
    "text",
    [_lines(GOOD, 9, 10), _lines(GOOD, replace={8: "1,1001,R2,,10", 9: "1,1001,R3,nan,10"})],
    ids=["rows missing", "toa missing"],
)
def test_an_epoch_with_three_receivers_has_a_no_fix_row_and_the_others_solve(tmp_path, text):
    res = _bad(tmp_path, text)
    assert res.fix.ok.tolist() == [True, False, True]
    assert res.fix.status.tolist() == ["", "too few receivers", ""]
    t = ts.solve_report(res.meas, ts.SolveConfig(), res).table
    row = dict(zip(t.columns, t.rows[1], strict=True))
    assert row["status"] == "no fix: 3 receiver(s), a fix needs 4" and row["x_m"] is None
    assert row["converged"] is False


def test_the_good_record_of_the_bad_ones_is_good(tmp_path):
    res = _bad(tmp_path, GOOD)
    assert res.fix.converged.all() and len(res.fix_epochs) == 3


TRACK = ts.SolveConfig(clock="track", sigma0_ns=20.0)


def test_track_needs_a_first_epoch_with_four_and_a_grid(tmp_path):
    three = _lines(GOOD, 5, 6)
    meas = ts.read_measurements(_write(tmp_path, three), receivers=_write(tmp_path, RX, "r.csv"))
    with pytest.raises(
        InputError, match=r"m.csv:2: column 'toa': epoch 0: 3 receiver\(s\): the clock track starts"
    ):
        ts.solve(meas, TRACK)
    later = _lines(GOOD, 10, 11)  # epoch 1 with three receivers: fine with the tracker
    meas = ts.read_measurements(_write(tmp_path, later), receivers=_write(tmp_path, RX, "r.csv"))
    res = ts.solve(meas, TRACK)
    assert res.track.mode == ("init", "outage", "update") and res.fix.ok.tolist() == [True, False, True]
    uneven = GOOD.replace("epoch,", "pulse_id,").replace(",1002,", ",1002.5,")
    meas = ts.read_measurements(
        _write(tmp_path, uneven), receivers=_write(tmp_path, RX, "r.csv"), columns="epoch=pulse_id"
    )
    ts.solve(meas, TRACK)  # epoch numbers are the steps: uneven times are fine
    no_epoch = "\n".join(",".join(r.split(",")[1:]) for r in uneven.splitlines()) + "\n"
    meas = ts.read_measurements(_write(tmp_path, no_epoch), receivers=_write(tmp_path, RX, "r.csv"))
    with pytest.raises(
        InputError,
        match=r"m.csv:\d+: column 'time': time 100\d s is .* periods off the .* grid.*--clock track needs",
    ):
        ts.solve(meas, TRACK)


def _write(tmp_path, text, name="m.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


CONFIG_ERRORS = {
    "track without sigma": ({"text": GOOD.replace(",sigma [ns]", "").replace(",10\n", "\n")}, TRACK, "sigma_ns"),
    "known covariance without sigma": ({"text": GOOD.replace(",sigma [ns]", "").replace(",10\n", "\n")},
                                       ts.SolveConfig(covariance="known"), "covariance"),
    "unknown unit role": ({"units": "bogus=ns"}, ts.SolveConfig(), "units"),
    "bad unit": ({"units": "toa=furlong"}, ts.SolveConfig(), "units"),
    "bad column role": ({"columns": "bogus=toa"}, ts.SolveConfig(), "columns"),
    "receivers columns without receivers": ({"receivers_columns": "x=east", "rx": False}, ts.SolveConfig(), "receivers_columns"),
    "bad receivers columns": ({"receivers_columns": "bogus=lat"}, ts.SolveConfig(), "receivers_columns"),
    "positions twice": ({"text": "epoch,receiver,toa,x,y,z\n0,R1,0.0001,6378137,0,0\n"}, ts.SolveConfig(), "receivers"),
}  # fmt: skip


@pytest.mark.parametrize("name", list(CONFIG_ERRORS))
def test_bad_options_name_their_field(tmp_path, name):
    kw, cfg, field = CONFIG_ERRORS[name]
    kw = dict(kw)
    p = _write(tmp_path, kw.pop("text", GOOD))
    r = _write(tmp_path, RX, "r.csv") if kw.pop("rx", True) else None
    with pytest.raises(ConfigError) as exc:
        ts.solve(ts.read_measurements(p, receivers=r, **kw), cfg)
    assert exc.value.field == field


@pytest.mark.parametrize(
    ("kw", "field"),
    [({"clock": "x"}, "clock"), ({"sigma_ns": 0.0}, "sigma_ns"), ({"sigma0_ns": -1.0, "clock": "track"}, "sigma0_ns"),
     ({"relinearise": 11, "clock": "track"}, "relinearise"), ({"units": "imperial"}, "units"),
     ({"start": (91.0, 0.0, 0.0)}, "start"), ({"gain": "steady"}, "gain"), ({"sigma0_ns": 5.0}, "sigma0_ns"),
     ({"max_iter": 0}, "max_iter"), ({"view": "x"}, "view"), ({"toa_origin": "x"}, "toa_origin")],
)  # fmt: skip
def test_configuration_checks_its_fields(kw, field):
    with pytest.raises(ConfigError) as exc:
        ts.SolveConfig(**kw)
    assert exc.value.field == field


# --- absolute times of arrival: exact to the last digit ---------------------------------------------------

UNIX_T0 = 1_777_629_600
"""2026-05-01T10:00:00Z as Unix seconds: float64 resolves 2.4e-7 s (71 m of range) there."""


def _absolute_case():
    """Five ground receivers (pymap3d, WGS-84), a transmitter at 3–3.05 km over six 1 s epochs emitting
    b_n = (1 n + 0.25) µs late: exact TOAs T = t_n + b_n + |p − s_k|/c as decimals (the float64 of
    b_n + |p − s_k|/c, ~5e-5 s, carries 1e-20 s), and the matrix H = [−u', 1] at the truth."""
    geo = np.array([(48.3538, 11.7861, 453.0), (48.3716, 11.9885, 500.9), (48.4256, 11.6240, 449.3),
                    (48.2279, 11.8265, 529.1), (48.30, 11.70, 480.0)])  # fmt: skip
    S = np.stack(pymap3d.geodetic2ecef(*geo.T), axis=-1)
    n = np.arange(6)
    P = np.stack(pymap3d.geodetic2ecef(48.35 + 0.001 * n, 11.80 + 0.002 * n, 3000.0 + 10.0 * n), axis=-1)
    b = 1e-6 * n + 2.5e-7
    d = np.linalg.norm(P[:, None] - S[None], axis=-1)  # (E, K) [m]
    offset = [[Decimal(repr(float(b[e] + d[e, k] / C))) for k in range(5)] for e in range(6)]
    u = (P[:, None] - S[None]) / d[..., None]
    H = np.concatenate([u, np.ones((6, 5, 1))], axis=-1)
    return S, P, b, offset, H


def _write_rx(tmp_path, S):
    path = tmp_path / "rx.csv"
    path.write_text(
        "receiver,x,y,z\n" + "".join(f"S{k},{x!r},{y!r},{z!r}\n" for k, (x, y, z) in enumerate(S.tolist()))
    )
    return path


def _linear_error(H, drho):
    """The least-squares error (δp, δb) that TOA errors δρ [m] cause at the truth: pinv(H) δρ (the fix is
    linear in δρ to first order; the second order, |δρ|²/range ≈ 1e-6 m, is far below these bounds)."""
    return np.einsum("eij,ej->ei", np.linalg.pinv(H), drho)


def test_unix_second_toas_with_12_decimals_give_the_position_to_a_millimetre(tmp_path):
    """TOAs as Unix seconds with 12 decimals (1777629600.000009522708): read as decimals and differenced from
    each epoch's time, the noise-free fixes are exact to < 1 mm (parsed as float64 first, as before, the
    errors were 10–95 m). The text's rounding (≤ 5e-13 s = 0.15 mm of range) predicts the error:
    pinv(H) δρ within 0.05 mm; the bound ‖pinv(H)[:3]‖₂ ‖δρ‖₂ holds."""
    S, P, b, offset, H = _absolute_case()
    q = Decimal("1e-12")
    rows, drho = [], np.zeros((6, 5))
    for e in range(6):
        t = UNIX_T0 + e
        for k in range(5):
            toa = Decimal(t) + offset[e][k].quantize(q)
            drho[e, k] = float(toa - t - offset[e][k]) * C
            rows.append(f"{e},{t},S{k},{toa}\n")
    m = tmp_path / "toa.csv"
    m.write_text("epoch,time,receiver,toa\n" + "".join(rows))
    assert "1777629600.0000" in m.read_text()  # absolute, with 12 decimals
    meas = ts.read_measurements(m, receivers=_write_rx(tmp_path, S))
    res = ts.solve(meas, ts.SolveConfig())
    err = np.linalg.norm(res.fix.position - P, axis=1)
    assert np.all(err < 1e-3), err
    lin = _linear_error(H, drho)
    np.testing.assert_allclose(res.fix.position - P, lin[:, :3], rtol=0, atol=5e-5)
    np.testing.assert_allclose(res.fix.clock_offset_s, b + lin[:, 3] / C, rtol=0, atol=1e-15)
    bound = np.linalg.norm(np.linalg.pinv(H)[:, :3], ord=2, axis=(1, 2)) * np.linalg.norm(drho, axis=1)
    assert np.all(err <= bound + 1e-6), (err, bound)
    meta = ts.solve_report(meas, ts.SolveConfig(), res).table.meta
    assert meta["reading"]["first_epoch_time_s"] == str(UNIX_T0)
    assert meta["reading"]["toa_minus"].startswith("its epoch's time")


def test_integer_nanosecond_toas_are_exact_up_to_their_rounding(tmp_path):
    """TOAs and times in integer nanoseconds since the Unix epoch (``toa [ns]`` = 1777629600000009523; the
    float64 of such an integer is off by up to 128 ns): the fixes err only by the nanosecond rounding of
    the text, |δT| ≤ 0.5 ns (0.15 m of range): their error is pinv(H) δρ within 0.1 mm and below the
    bound ‖pinv(H)[:3]‖₂ ‖δρ‖₂ (≤ 0.5 m here); measured 0.08–0.26 m. The same as a JSON document with
    integers (exact in JSON)."""
    S, P, b, offset, H = _absolute_case()
    rows, drho, data = [], np.zeros((6, 5)), []
    for e in range(6):
        t_ns = (UNIX_T0 + e) * 10**9
        for k in range(5):
            toa_ns = t_ns + int((offset[e][k] * 10**9).to_integral_value())  # nearest ns
            drho[e, k] = float(Decimal(toa_ns - t_ns) / 10**9 - offset[e][k]) * C
            rows.append(f"{e},{t_ns},S{k},{toa_ns}\n")
            data.append({"epoch": e, "time [ns]": t_ns, "receiver": f"S{k}", "toa [ns]": toa_ns})
    assert np.all(np.abs(drho) <= 0.5e-9 * C)
    m = tmp_path / "toa_ns.csv"
    m.write_text("epoch,time [ns],receiver,toa [ns]\n" + "".join(rows))
    j = tmp_path / "toa_ns.json"
    j.write_text(json.dumps({"meta": {}, "columns": list(data[0]), "data": data}, indent=1))
    rx = _write_rx(tmp_path, S)
    lin = _linear_error(H, drho)
    bound = np.linalg.norm(np.linalg.pinv(H)[:, :3], ord=2, axis=(1, 2)) * np.linalg.norm(drho, axis=1)
    for path in (m, j):
        meas = ts.read_measurements(path, receivers=rx)
        assert meas.record.units["toa"] == "ns"
        res = ts.solve(meas, ts.SolveConfig())
        err = np.linalg.norm(res.fix.position - P, axis=1)
        assert np.all(err <= bound + 1e-6) and np.all(bound < 0.5), (err, bound)
        np.testing.assert_allclose(res.fix.position - P, lin[:, :3], rtol=0, atol=1e-4, err_msg=str(path))
        np.testing.assert_allclose(res.fix.clock_offset_s, b + lin[:, 3] / C, rtol=0, atol=1e-13)
        np.testing.assert_array_equal(meas.time, UNIX_T0 + np.arange(6.0))  # correctly rounded seconds
        assert meas.first_time == str(UNIX_T0)


def test_pseudoranges_in_kilometres_are_read_with_one_rounding(tmp_path):
    """Pseudoranges c(T − t) in km with 15 decimals (1e-12 km = 1 nm): read as decimals times 1000, each
    row's float64 is the correctly rounded value in metres (one rounding; float(text) × 1000 is two), and
    the fixes are exact to < 1 mm."""
    S, P, b, offset, _ = _absolute_case()
    text = ["epoch,receiver,pseudorange [km]\n"]
    want = []
    for e in range(6):
        for k in range(5):
            km = (offset[e][k] * Decimal(C) / 1000).quantize(Decimal("1e-15"))
            text.append(f"{e},S{k},{km}\n")
            want.append(float(km * 1000))
    m = tmp_path / "pr.csv"
    m.write_text("".join(text))
    meas = ts.read_measurements(m, receivers=_write_rx(tmp_path, S))
    assert meas.rho.ravel().tolist() == want
    res = ts.solve(meas, ts.SolveConfig())
    assert np.all(np.linalg.norm(res.fix.position - P, axis=1) < 1e-3)
    np.testing.assert_allclose(res.fix.clock_offset_s, b, rtol=0, atol=1e-14)


def test_receivers_file_column_errors_name_its_option(tmp_path):
    """A receivers file's column mapping is --receivers-columns in every message about it."""
    m = _write(tmp_path, GOOD)
    r = _write(tmp_path, RX, "r.csv")
    with pytest.raises(InputError, match=r"r.csv:1: no column 'foo' for --receivers-columns receiver=foo"):
        ts.read_measurements(m, receivers=r, receivers_columns="receiver=foo")
    both = _write(tmp_path, RX.replace("receiver,", "receiver,id,").replace(",48.", ",x,48."), "r2.csv")
    with pytest.raises(InputError, match=r"could both be the receiver; say which with --receivers-columns"):
        ts.read_measurements(m, receivers=both)
