"""The track-existence test on the user's own detections (``slrt --input``): the files written from a
simulated run read back to the same scores bit for bit; sensors with their own noise, p_D and clutter
against an independent loop oracle; records written here by independent numpy/csv code (a target at
constant velocity seen by three radars in uniform clutter, ISO 8601 times, bearings in degrees) confirm
the target, and the same radars' clutter alone does not; one sensor makes the fusion rules coincide; every
bad input is named by file, line and column."""

import csv
import math
from dataclasses import replace
from datetime import UTC, datetime, timedelta

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.sprt import wald_thresholds
from motionsig_cli.detection.track_existence import METHODS, SensorModel, run_methods
from motionsig_cli.errors import InputError
from motionsig_cli.existence import slrt
from motionsig_cli.existence import slrt_record as sr
from motionsig_cli.models.radar import MeasurementModel
from motionsig_cli.tables import format_csv, format_json
from tests.detection import slrt_oracle as orc


# ------------------------------------------------------------------ a simulated run, written and read back
def _write_run(tmp_path, study, fmt="csv"):
    render = format_csv if fmt == "csv" else format_json
    d, s = tmp_path / f"dets.{fmt}", tmp_path / f"sensors.{fmt}"
    d.write_text(render(sr.detection_table(study)))
    s.write_text(render(sr.sensor_table(study)))
    return d, s


@pytest.mark.parametrize(
    ("kw", "fmt"),
    [
        ({}, "csv"),
        ({"clutter_rate": 0.3}, "json"),  # many sensor-scans without detections: rows with empty cells
        ({"meas_model": "cartesian", "clutter_rate": 2.0}, "csv"),
        ({"T": 0.1, "q": 3.0, "n_sensors": 3, "scans": 12}, "csv"),  # T from the metadata, not estimated
        ({"n_sensors": 1, "scans": 10}, "csv"),
    ],
)
def test_files_of_a_simulated_run_give_its_scores_bit_for_bit(tmp_path, kw, fmt):
    sc = replace(slrt.SlrtScenario(scans=15), **kw)
    study = slrt.SlrtStudy(sc, pd=(0.5,), no_target=False, runs=1, seed=11)
    sim, _ = slrt.run(study.cases[0][1], 1, 11)
    d, s = _write_run(tmp_path, study, fmt)
    cfg = sr.SlrtRecordConfig(q=sc.q)
    res = sr.score(sr.load(d, s, cfg), cfg)
    assert res.tracks.m0.shape == (1, 4) and res.tracks.first == 0
    for m in METHODS:
        np.testing.assert_array_equal(res.scores[m][0], sim[m][0])  # float-exact
    assert res.record.detections.T_source == "the file's metadata 'T'"
    if kw.get("clutter_rate") == 0.3:
        text = d.read_text()
        assert text.count('"range [m]": null') > 10  # JSON nulls for the empty measurement cells
    # run 0 of a larger Monte Carlo batch is the same run: the same scores (the filters are batch-invariant)
    many, _ = slrt.run(study.cases[0][1], 6, 11)
    for m in METHODS:
        np.testing.assert_array_equal(res.scores[m][0], many[m][0])


def test_written_detections_are_the_runs_measurements(tmp_path):
    """The file holds exactly the generated measurements (target first per sensor, then clutter) and a row
    with empty cells for each sensor-scan without any."""
    sc = slrt.SlrtScenario(scans=8, clutter_rate=0.5, pd_true=0.5, pd_filter=0.5)
    study = slrt.SlrtStudy(sc, pd=(0.5,), no_target=False, runs=1, seed=4)
    t = sr.detection_table(study)
    gen = slrt.generate(study.cases[0][1], range(1), 4)
    rows = {(r[0], r[2]): [] for r in t.rows}
    for r in t.rows:
        rows[(r[0], r[2])].append(r)
    for k in range(sc.scans):
        for s in range(sc.n_sensors):
            z = gen.scans[k].Z[s][0][gen.scans[k].valid[s][0]]
            got = rows[(k + 1, f"radar{s + 1}")]
            if len(z) == 0:
                assert [(r[3], r[4], r[5]) for r in got] == [(None, None, "")]
            else:
                assert [(r[3], r[4]) for r in got] == [tuple(v) for v in z.tolist()]
                n_t = len(z) - gen.clutter_counts[0, k, s]
                assert [r[5] for r in got] == ["target"] * n_t + ["clutter"] * (len(z) - n_t)
    assert t.meta["init"] == gen.m0[0].tolist() and t.meta["T"] == 1.0


# ------------------------------------------------------------------ sensors that differ
def _oracle(data, sensors, F, Q, m0, P0, pds, rhos, Rs, kind):
    """CKF, DKF and LKF of one run, one sensor at a time, with each sensor's own R, p_D and ρ_F, from the
    independent oracle's local update and product constant (tests/detection/slrt_oracle.py)."""
    S = len(sensors)
    models = [orc._sensor_model(np.asarray(p, float), kind) for p in sensors]

    def upd(m, P, s, Z):
        h, jac, wi = models[s]
        return orc.local_update(m, P, Z, h, jac, Rs[s], pds[s], rhos[s], wi)

    out = {k: [] for k in ("ckf", "fkf", "lkf")}
    m, P, total = m0.copy(), P0.copy(), 0.0
    for scan in data:
        m, P = F @ m, orc._sym(F @ P @ F.T + Q)
        for s in range(S):
            m, P, lp = upd(m, P, s, scan[s])
            total += lp
        out["ckf"].append(total)
    loc, score = [(m0.copy(), P0.copy()) for _ in range(S)], np.zeros(S)
    for scan in data:
        for s in range(S):
            m, P = loc[s]
            m, P, lp = upd(F @ m, orc._sym(F @ P @ F.T + Q), s, scan[s])
            loc[s], score[s] = (m, P), score[s] + lp
        top = score.max()
        out["lkf"].append(top + math.log(np.mean(np.exp(score - top))))
    loc, total = [(m0.copy(), S * P0) for _ in range(S)], 0.0
    for scan in data:
        pred = [(F @ m, orc._sym(F @ P @ F.T + S * Q)) for m, P in loc]
        c0 = orc.gaussian_product_constant_closed([p[0] for p in pred], [p[1] for p in pred])
        lam = 0.0
        for s in range(S):
            m, P, lp = upd(*pred[s], s, scan[s])
            loc[s], lam = (m, P), lam + lp
        c1 = orc.gaussian_product_constant_closed([p[0] for p in loc], [p[1] for p in loc])
        total += lam + c1 - c0
        out["fkf"].append(total)
    return {k: np.array(v) for k, v in out.items()}


@pytest.mark.parametrize("kind", ["range_bearing", "cartesian"])
def test_sensors_with_their_own_noise_pd_and_clutter_equal_the_loop_oracle(kind):
    sc = slrt.SlrtScenario(n_sensors=3, scans=10, clutter_rate=3.0, meas_model=kind)
    gen = slrt.generate(sc, range(3), 21)
    base = sc.model()
    pds, rates, fovs = (0.9, 0.6, 0.95), (3.0, 10.0, 0.5), (26_000.0, 30_000.0, 40_000.0)
    Rs = [np.diag([40.0**2, math.radians(0.1) ** 2]), np.diag([90.0**2, math.radians(0.4) ** 2]),
          np.diag([60.0**2, math.radians(0.2) ** 2])] if kind == "range_bearing" else [
          np.diag([40.0**2, 40.0**2]), np.diag([90.0**2, 90.0**2]), np.diag([25.0**2, 25.0**2])]  # fmt: skip
    sms = tuple(
        SensorModel(MeasurementModel(kind, R, f), p, c)
        for R, f, p, c in zip(Rs, fovs, pds, rates, strict=True)
    )
    model = replace(base, sensor_models=sms)
    out = run_methods(model, gen.m0, gen.scans)
    for r in range(3):
        data = [[scan.Z[s][r][scan.valid[s][r]] for s in range(3)] for scan in gen.scans]
        o = _oracle(data, list(sc.sensors), model.F, model.Q, gen.m0[r], model.m0_cov, pds,
                    [math.exp(sm.log_rho) for sm in sms], Rs, kind)  # fmt: skip
        for m in METHODS:
            np.testing.assert_allclose(out[m][r], o[m], rtol=1e-9, atol=1e-7)
    # the shared values would give other scores: the per-sensor values are used
    assert not np.allclose(run_methods(base, gen.m0, gen.scans)["ckf"], out["ckf"])


def test_per_sensor_values_that_are_all_equal_give_the_shared_scores_bit_for_bit():
    sc = slrt.SlrtScenario(n_sensors=3, scans=12, clutter_rate=8.0)
    gen = slrt.generate(sc, range(5), 3)
    base = sc.model()
    same = replace(base, sensor_models=(SensorModel(base.meas, base.pd, base.clutter_rate),) * 3)
    a, b = run_methods(base, gen.m0, gen.scans), run_methods(same, gen.m0, gen.scans)
    for m in METHODS:
        np.testing.assert_array_equal(a[m], b[m])


def test_sensor_models_must_match_the_sensors():
    base = slrt.SlrtScenario(n_sensors=2).model()
    sm = SensorModel(base.meas, 0.9, 1.0)
    with pytest.raises(ConfigError) as err:
        replace(base, sensor_models=(sm,))
    assert err.value.field == "sensor_models"
    other = SensorModel(MeasurementModel("cartesian", np.eye(2), 1e4), 0.9, 1.0)
    with pytest.raises(ConfigError):
        replace(base, sensor_models=(sm, other))
    with pytest.raises(ConfigError) as err:
        SensorModel(base.meas, 1.5, 1.0)
    assert err.value.field == "pd"


# ------------------------------------------------------------------ records written by independent code
SENSORS = [  # label, x, y, sigma_r [m], sigma_phi [deg], p_D, false alarms per scan, fov [m]
    ("north", -12_000.0, 4_000.0, 30.0, 0.15, 0.9, 4.0, 30_000.0),
    ("east", 14_000.0, -2_000.0, 45.0, 0.25, 0.8, 6.0, 32_000.0),
    ("south", 1_000.0, -15_000.0, 60.0, 0.3, 0.95, 2.0, 28_000.0),
]
T_SCAN, N_SCANS, SKIPPED = 2.0, 20, 7  # scan 8 (index 7): no sensor detected anything (no row at all)
P1, V = np.array([2_000.0, -1_000.0]), np.array([120.0, -80.0])  # position at the first scan, velocity
T0 = datetime(2026, 5, 1, 12, 0, 0, tzinfo=UTC)


def write_sensors(path, sensors=SENSORS):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["Sensor", "X", "Y", "sigma_r", "sigma_phi", "pd", "clutter", "fov"])
        for row in sensors:
            w.writerow(row)


def write_detections(path, seed, *, target=True, sensors=SENSORS):
    """A record as a radar export might hold it, drawn here with numpy: a target at constant velocity (if
    ``target``), each radar detecting it with its p_D (noise σ_r, σ_φ), Poisson false alarms uniform over
    each field of view in range and bearing (the filters' clutter model), rows of a scan in a shuffled
    order, ISO 8601 times, bearing in degrees. Returns the target's detections: (scan, sensor) → (x, y)."""
    rng = np.random.default_rng(seed)
    rows, truth_dets = [], {}
    for k in range(N_SCANS):
        if k == SKIPPED:
            continue
        p = P1 + V * (k * T_SCAN)
        stamp = (T0 + timedelta(seconds=k * T_SCAN)).isoformat().replace("+00:00", "Z")
        scan_rows = []
        for lab, sx, sy, sr_, sphi, pd, lam, fov in sensors:
            if target and rng.random() < pd:
                d = p - (sx, sy)
                r = math.hypot(*d) + sr_ * rng.standard_normal()
                b = math.atan2(d[1], d[0]) + math.radians(sphi) * rng.standard_normal()
                scan_rows.append((stamp, lab, r, math.degrees(b)))
                truth_dets[(k, lab)] = (sx + r * math.cos(b), sy + r * math.sin(b))
            for _ in range(rng.poisson(lam)):
                scan_rows.append((stamp, lab, rng.uniform(0, fov), rng.uniform(-180.0, 180.0)))
        rng.shuffle(scan_rows)
        rows.extend(scan_rows)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["timestamp", "sensor", "Range", "Bearing (deg)"])
        w.writerows(rows)
    return truth_dets


INIT = tuple(
    float(v) for v in (*(P1 - V * T_SCAN + (150.0, -100.0)), *V)
)  # x, y one period before the first scan, 180 m off
INIT_XVY = (INIT[0], INIT[2], INIT[1], INIT[3])  # as x, vx, y, vy


def _score(tmp_path, *, target, seed, init=INIT_XVY):
    d, s = tmp_path / "export.csv", tmp_path / "radars.csv"
    dets = write_detections(d, seed, target=target)
    write_sensors(s)
    cfg = sr.SlrtRecordConfig(init=init)
    rec = sr.load(d, s, cfg)
    return sr.score(rec, cfg), dets


def test_an_independent_record_of_a_target_is_confirmed(tmp_path):
    res, _ = _score(tmp_path, target=True, seed=1)
    det = res.record.detections
    assert det.T == T_SCAN and det.T_source == "estimated from the time column"
    assert det.n_scans == N_SCANS and det.counts(3)[SKIPPED].sum() == 0  # the absent scan: nothing detected
    assert res.record.detections.record.time_origin == "2026-05-01T12:00:00+00:00"
    assert not res.record.sensors.uniform  # each radar's own noise, p_D and clutter
    log_a, log_b = wald_thresholds(1e-3, 0.1)
    ckf = res.scores["ckf"][0]
    # each scan the target's detections add about log(p_D N(ν; S)/ρ_F) ≈ 7–12 per radar: log B is crossed
    # in the first scans, and never log A before (a deletion would need the target missed by all radars)
    assert ckf.max() >= log_b and np.all(ckf[: np.argmax(ckf >= log_b)] > log_a)
    for m in METHODS:
        dec, at = res.decisions(m)
        assert dec[0] == 1 and at[0] <= 3, (m, at)
    # through the missed scan the score drops by about Σ log(1 − p_D) = log(0.1·0.2·0.05) ≈ −7.6
    drop = res.scores["ckf"][0, SKIPPED] - res.scores["ckf"][0, SKIPPED - 1]
    assert -9.0 < drop < -6.5, drop


def test_the_same_radars_clutter_alone_is_not_confirmed(tmp_path):
    res, _ = _score(tmp_path, target=False, seed=2)
    log_a, _ = wald_thresholds(1e-3, 0.1)
    # no target: each scan costs about Σ_s log(1 − p_D) ≈ −7.6 unless clutter falls on the track, so CKF
    # and DKF fall below log A at the first scan, LKF (the mean of the radars' LRs) by the second; Wald
    # bounds a confirmation by α/(1 − β) ≈ 1.1e-3
    for m in METHODS:
        dec, at = res.decisions(m)
        assert dec[0] == -1 and at[0] <= 1, (m, at)
    assert res.scores["ckf"][0, 0] < log_a


def test_tracks_started_from_the_first_scan_find_the_target(tmp_path):
    """Without --init: one tentative track per detection of scan 1; those from the target's detections
    confirm, those from false alarms far from it are deleted."""
    res, dets = _score(tmp_path, target=True, seed=3, init=None)
    tr = res.tracks
    assert tr.first == 1 and tr.m0.shape[0] == res.record.detections.counts(3)[0].sum() > 3
    start_xy = tr.m0[:, [0, 2]]
    from_target = np.array([(0, lab) in dets and np.allclose(xy, dets[(0, lab)])
                            for xy, (lab, _) in zip(start_xy, tr.starts, strict=True)])  # fmt: skip
    assert from_target.sum() >= 2
    far = np.hypot(*(start_xy - P1).T) > 2_000.0
    assert far.sum() >= 5
    dec, _ = res.decisions("ckf")
    assert np.all(dec[from_target] == 1)
    assert np.all(dec[far] != 1)  # each of these false tracks: P(confirm) ≤ α/(1 − β) ≈ 1e-3
    rows = res.table("decisions").rows
    assert {r[8] for r in rows} <= {lab for lab, *_ in SENSORS} and all(isinstance(r[9], int) for r in rows)


def test_tracks_started_from_clutter_alone_are_not_confirmed(tmp_path):
    res, _ = _score(tmp_path, target=False, seed=4, init=None)
    assert res.tracks.m0.shape[0] >= 5
    for m in METHODS:
        dec, _ = res.decisions(m)
        assert np.all(dec != 1), m  # ~12 tracks, each confirmed with probability ≤ 1.1e-3


def test_one_sensor_makes_the_fusion_rules_coincide(tmp_path):
    d, s = tmp_path / "one.csv", tmp_path / "one_sensor.csv"
    write_detections(d, 5, sensors=SENSORS[:1])
    write_sensors(s, SENSORS[:1])
    cfg = sr.SlrtRecordConfig(init=INIT_XVY)
    res = sr.score(sr.load(d, s, cfg), cfg)
    np.testing.assert_array_equal(res.scores["ckf"], res.scores["fkf"])
    np.testing.assert_array_equal(res.scores["ckf"], res.scores["lkf"])
    assert res.table("curves").meta["single_sensor"].startswith("one sensor: the fusion rules coincide")
    assert any("coincide" in n for n in res.notes())
    cfg_log = replace(cfg, lkf_mean="log")
    np.testing.assert_array_equal(sr.score(sr.load(d, s, cfg_log), cfg_log).scores["lkf"], res.scores["ckf"])


def test_tables_of_a_record(tmp_path):
    res, _ = _score(tmp_path, target=True, seed=1)
    t = res.table("curves")
    assert t.columns == sr.RECORD_SCAN_COLUMNS and len(t.rows) == 3 * N_SCANS
    ckf = [r for r in t.rows if r[1] == "ckf"]
    assert [r[2] for r in ckf] == list(range(1, N_SCANS + 1))
    assert [r[3] for r in ckf] == [k * T_SCAN for k in range(N_SCANS)]  # seconds after the first timestamp
    assert ckf[SKIPPED][4] == 0
    states = [r[6] for r in ckf]
    first = states.index("confirmed")
    assert set(states[:first]) <= {"undecided"} and set(states[first:]) == {"confirmed"}
    d = res.table("decisions")
    assert [r[2] for r in d.rows] == ["confirmed"] * 3 and d.rows[0][8] is None  # an --init track
    meta = t.meta
    assert meta["per_sensor_values"] is True and meta["T_source"] == "estimated from the time column"
    assert meta["detections"]["input_units"]["bearing"] == "deg"
    assert meta["sensor_table"]["input_units"]["sigma_phi"] == "deg"
    assert meta["init"]["state"] == list(INIT_XVY)
    assert "spec" not in str(meta).lower()


def test_stop_freezes_the_score_at_the_decision(tmp_path):
    d, s = tmp_path / "export.csv", tmp_path / "radars.csv"
    write_detections(d, 1)
    write_sensors(s)
    cfg = sr.SlrtRecordConfig(init=INIT_XVY, stop=True)
    res = sr.score(sr.load(d, s, cfg), cfg)
    _, at = res.decisions("ckf")
    v = res.scores["ckf"][0]
    assert np.all(v[at[0] :] == v[at[0]])


# ------------------------------------------------------------------ scans, times, units and columns
def _files(tmp_path, dets, sensors="sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,0.9,2,20000\n"):
    d, s = tmp_path / "d.csv", tmp_path / "s.csv"
    d.write_text(dets)
    s.write_text(sensors)
    return d, s


def test_scan_numbers_cartesian_columns_mapping_and_units(tmp_path):
    d, s = _files(
        tmp_path,
        "# T: 4\nscan_no,radar,east_km,north_km\n5,A,1,2\n5,A,,\n7,A,1.5,2.5\n",
        "name,x,y,sigma_xy,pd,clutter_density,fov [km]\nA,0,0,50,0.9,1e-9,20\n",
    )
    cfg = sr.SlrtRecordConfig(init=(0.0, 100.0, 0.0, 100.0))
    rec = sr.load(d, s, cfg, columns="scan=scan_no,x=east_km,y=north_km", units="x=km,y=km")
    det = rec.detections
    assert det.kind == "cartesian" and det.n_scans == 3 and det.T == 4.0
    np.testing.assert_array_equal(det.z, [[1000.0, 2000.0], [1500.0, 2500.0]])
    assert det.counts(1).ravel().tolist() == [1, 0, 1]
    sm = rec.sensors.models[0]
    assert sm.meas.fov_range == 20_000.0 and sm.clutter_rate == pytest.approx(1e-9 * 40_000.0**2)
    # x, y in --units apply to both files: the sensor position in km too
    assert rec.sensors.positions.tolist() == [[0.0, 0.0]]


def test_scan_numbers_without_times_assume_one_second(tmp_path):
    d, s = _files(tmp_path, "scan,sensor,range,bearing\n1,A,100,0.1\n3,A,200,0.2\n")
    rec = sr.load(d, s, sr.SlrtRecordConfig())
    assert rec.detections.T == 1.0 and rec.detections.T_source.startswith("assumed: 1 s")
    assert rec.detections.n_scans == 3 and rec.detections.times.tolist() == [0.0, 1.0, 2.0]


def test_scan_numbers_with_the_times_a_rotating_antenna_stamps(tmp_path):
    """With scan numbers, each detection's own time stamp may lie anywhere in its scan, in any order:
    the period is the least-squares slope of the scans' first times (here 4 s, from times up to 3.5 s
    late), each scan's time its first row's."""
    rng = np.random.default_rng(0)
    lines = []
    for k in range(0, 40):
        if k == 5:
            continue  # no detection at all in scan 5
        for _ in range(3):
            lines.append(
                f"{k},{4.0 * k + rng.uniform(0, 3.5):.3f},A,{rng.uniform(0, 2e4)},{rng.uniform(-3, 3)}"
            )
    d, s = _files(tmp_path, "scan,time,sensor,range,bearing\n" + "\n".join(lines) + "\n")
    det = sr.load(d, s, sr.SlrtRecordConfig()).detections
    # σ(T̂) = σ_t/√(Σ(k − k̄)²) ≈ 1.0/√5000 ≈ 0.015 s for jitter uniform over 3.5 s
    assert det.T == pytest.approx(4.0, abs=0.06) and det.T_source.startswith("estimated from the times")
    assert det.n_scans == 40 and det.counts(1)[5, 0] == 0
    assert det.times[0] == float(lines[0].split(",")[1])


def test_a_record_without_detections_after_the_first_needs_init(tmp_path):
    d, s = _files(tmp_path, "time,sensor,range,bearing\n0,A,100,0.1\n1,A,,\n")
    res = sr.score(sr.load(d, s, sr.SlrtRecordConfig()), sr.SlrtRecordConfig())
    assert res.tracks.m0.shape[0] == 1 and res.scores["ckf"].shape == (1, 1)  # scored from scan 2
    assert res.tracks.starts == [("A", 2)]
    d, s = _files(tmp_path, "time,sensor,range,bearing\n0,A,,\n1,A,100,0.1\n")
    with pytest.raises(InputError, match=r"d.csv:3: no scan after the first with detections .* --init"):
        sr.score(sr.load(d, s, sr.SlrtRecordConfig()), sr.SlrtRecordConfig())
    d, s = _files(tmp_path, "time,sensor,range,bearing\n0,A,,\n1,A,,\n")
    with pytest.raises(InputError, match=r"no detection to start a track from: give --init"):
        sr.score(sr.load(d, s, sr.SlrtRecordConfig()), sr.SlrtRecordConfig())


S_OK = "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,0.9,2,20000\nB,1e4,0,50,0.2,0.9,2,20000\n"
D_OK = "time,sensor,range,bearing\n0,A,100,0.1\n1,B,100,0.1\n"


@pytest.mark.parametrize(
    ("dets", "sensors", "match"),
    [
        ("time,sensor,range,bearing\n0,A,100,0.1\n0,C,1,0\n", S_OK,
         r"d.csv:3: column 'sensor': sensor 'C' is not in the sensors table .*s.csv \(A, B\)"),
        ("time,sensor,range\n0,A,100\n", S_OK, r"d.csv:1: missing column 'bearing'"),
        ("time,sensor,x\n0,A,100\n", S_OK, r"d.csv:1: missing column 'y'"),
        ("sensor,range,bearing\nA,100,0.1\n", S_OK, r"d.csv:1: missing column 'time' \(or 'scan'\)"),
        ("time,range,bearing\n0,100,0.1\n", S_OK, r"d.csv:1: missing column 'sensor'"),
        ("time,sensor,range,bearing\n0,A,abc,0.1\n", S_OK, r"d.csv:2: column 'range': 'abc' is not a number"),
        ("time,sensor,range,bearing\n1,A,100,0.1\n0,A,100,0.1\n", S_OK,
         r"d.csv:3: column 'time': time goes backwards"),
        ("scan,sensor,range,bearing\n2,A,100,0.1\n1,A,100,0.1\n", S_OK, r"d.csv:3: column 'scan': scan goes backwards"),
        ("time,sensor,range,bearing\n0,A,100,0.1\n1,B,25000,0.1\n", S_OK,
         r"d.csv:3: column 'range': range 25000 m is beyond the field of view \(20000 m\) of sensor 'B' "
         r"\(.*s.csv:3\)"),
        ("time,sensor,range,bearing\n0,A,-1,0.1\n", S_OK, r"d.csv:2: column 'range': range -1 m is negative"),
        ("time,sensor,range,bearing\n0,A,100,45\n", S_OK, r"d.csv:2: column 'bearing': bearing 45 rad is beyond"),
        ("time,sensor,x,y\n0,A,100,25000\n", "sensor,x,y,sigma_xy,pd,clutter,fov\nA,0,0,50,0.9,2,2e4\n",
         r"d.csv:2: column 'y': y 25000 m is further than the field"),
        ("time,sensor,range [furlong],bearing\n0,A,100,0.1\n", S_OK,
         r"d.csv:1: column 'range \[furlong\]': unknown length unit 'furlong'"),
        ("", S_OK, r"d.csv: no header row"),
        ("time,sensor,range,bearing\n", S_OK, r"d.csv: no detections"),
        ("time,sensor,range,bearing\n0,A,100,\n", S_OK,
         r"d.csv:2: column 'bearing': missing while 'range' has a value"),
        ("time,sensor,range,bearing,x,y\n0,A,1,0,1,1\n", S_OK, r"d.csv:1: has both range,bearing and x,y"),
        ("time,sensor,range,bearing\n" + "".join(f"{t},A,1,0\n" for t in (0, 1, 2, 3, 4, 5.5)), S_OK,
         r"d.csv:7: column 'time': time 5.5 s is 0.5 periods off the 1 s grid"),
        ("time,sensor,range,bearing\n0,A,1,0\n", S_OK, r"d.csv:2: column 'time': all rows share one time"),
        ("# T: -1\ntime,sensor,range,bearing\n0,A,1,0\n", S_OK, r"d.csv: metadata 'T' = -1 is not a number"),
        ("scan,sensor,range,bearing\n0,A,1,0\n200000,A,1,0\n", S_OK,
         r"d.csv:3: column 'scan': is 200001 scans after the first row's \(at most 100000\)"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,0.9,2,2e4\nA,1,0,50,0.2,0.9,2,2e4\n",
         r"s.csv:3: column 'sensor': sensor 'A' is listed twice \(first at line 2\)"),
        (D_OK, "sensor,x,y,sigma_r,pd,clutter,fov\nA,0,0,50,0.9,2,2e4\n",
         r"s.csv:1: missing column 'sigma_phi' .* --sensor-columns sigma_phi=NAME"),
        (D_OK, "sensor,x,sigma_r,sigma_phi,pd,clutter,fov\nA,0,50,0.2,0.9,2,2e4\n",
         r"s.csv:1: missing column 'y'.*--sensor-columns y=NAME"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,fov\nA,0,0,50,0.2,0.9,2e4\n",
         r"s.csv:1: missing column 'clutter' \(or 'clutter_density'\)"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,clutter_density,fov\nA,0,0,50,0.2,0.9,2,1,2e4\n",
         r"s.csv:1: has both 'clutter' and 'clutter_density'"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,1.5,2,2e4\nB,0,0,50,0.2,0.9,2,2e4\n",
         r"s.csv:2: column 'pd': 1.5 is not in \(0, 1\]"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,1,2,2e4\nB,0,0,50,0.2,0.9,2,2e4\n",
         r"s.csv:2: column 'pd': p_D = 1 is only meaningful without clutter"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,0,0.2,0.9,2,2e4\nB,0,0,50,0.2,0.9,2,2e4\n",
         r"s.csv:2: column 'sigma_r': 0 is not in \[0.001, 100000\] m"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,0.9,two,2e4\n",
         r"s.csv:2: column 'clutter': 'two' is not a number"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\n", r"s.csv: no sensors"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi [arcmin],pd,clutter,fov\nA,0,0,50,1,0.9,2,2e4\n",
         r"s.csv:1: column 'sigma_phi \[arcmin\]': unknown angle unit 'arcmin'"),
        (D_OK, "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\n"
         + "".join(f"S{i},0,0,50,0.2,0.9,2,2e4\n" for i in range(65)), r"s.csv:66: more than 64 data rows"),
    ],
)  # fmt: skip
def test_bad_input_names_file_line_and_column(tmp_path, dets, sensors, match):
    d, s = _files(tmp_path, dets, sensors)
    with pytest.raises(InputError, match=match):
        rec = sr.load(d, s, sr.SlrtRecordConfig())
        sr.score(rec, sr.SlrtRecordConfig())


def test_a_file_longer_than_the_limit_is_refused_while_it_is_read(tmp_path):
    d, s = _files(tmp_path, "")
    n = sr.MAX_DETECTIONS + 1
    with open(d, "w") as f:  # 10^6 + 1 rows: refused at the first row beyond the limit
        f.write("time,sensor,range,bearing\n")
        f.writelines(f"{k},A,100,0.1\n" for k in range(n))
    with pytest.raises(InputError, match=rf"d.csv:{n + 1}: more than {sr.MAX_DETECTIONS} data rows"):
        sr.load(d, s, sr.SlrtRecordConfig())


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"q": -1.0}, "q"),
        ({"T": 0.0}, "T"),
        ({"T": 1e5}, "T"),
        ({"init": (1.0, 2.0, 3.0)}, "init"),
        ({"init": (1.0, 2.0, math.nan, 4.0)}, "init"),
        ({"init_sd": (1.0, 0.0)}, "init_sd"),
        ({"init_sd": (1.0,)}, "init_sd"),
        ({"meas": "polar"}, "meas"),
        ({"methods": ("ukf",)}, "methods"),
        ({"lkf_mean": "median"}, "lkf_mean"),
        ({"alpha": 0.5}, "alpha"),
        ({"beta": 0.0}, "beta"),
    ],
)
def test_config_rejects_each_bad_field_naming_it(kw, field):
    with pytest.raises(ConfigError) as err:
        sr.SlrtRecordConfig(**kw)
    assert err.value.field == field


def test_bad_columns_and_units_name_their_option(tmp_path):
    d, s = _files(tmp_path, D_OK, S_OK)
    for kw, field in (
        ({"units": "foo=m"}, "units"),
        ({"units": "bearing=furlong"}, "units"),
        ({"columns": "bogus=x"}, "columns"),
        ({"sensor_columns": "bogus=x"}, "sensor_columns"),
    ):
        with pytest.raises(ConfigError) as err:
            sr.load(d, s, sr.SlrtRecordConfig(), **kw)
        assert err.value.field == field, kw
    with pytest.raises(InputError, match=r"s.csv:1: no column 'prob' for --sensor-columns pd=prob"):
        sr.load(d, s, sr.SlrtRecordConfig(), sensor_columns="pd=prob")


def test_metadata_init_is_checked(tmp_path):
    d, s = _files(tmp_path, "# init: [1, 2, 3]\n" + D_OK, S_OK)
    with pytest.raises(InputError, match=r"d.csv: metadata 'init' = \[1, 2, 3\] is not 4 finite numbers"):
        sr.score(sr.load(d, s, sr.SlrtRecordConfig()), sr.SlrtRecordConfig())


def test_too_much_work_is_refused_before_it_starts(tmp_path):
    d, s = _files(tmp_path, "scan,sensor,range,bearing\n0,S0,1,0\n99999,S0,1,0\n",
                  "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\n"
                  + "".join(f"S{i},0,0,50,0.2,0.9,2,2e4\n" for i in range(64)))  # fmt: skip
    cfg = sr.SlrtRecordConfig(init=(0.0, 0.0, 0.0, 0.0))
    with pytest.raises(InputError, match=r"100000 scans x 64 sensors x 1 track\(s\) would take about"):
        sr.score(sr.load(d, s, cfg), cfg)


def test_equal_sensors_are_read_as_the_simulated_ones(tmp_path):
    """The sensors table of a simulated run gives the scenario's model values exactly."""
    study = slrt.SlrtStudy(slrt.SlrtScenario(scans=4), pd=(0.9,), no_target=False, runs=1)
    d, s = _write_run(tmp_path, study)
    rec = sr.load(d, s, sr.SlrtRecordConfig())
    model = study.cases[0][1].model()
    assert rec.sensors.uniform and rec.sensors.labels == ("radar1", "radar2", "radar3", "radar4")
    assert np.array_equal(model.sensors, rec.sensors.positions)
    for sm in rec.sensors.models:
        assert np.array_equal(model.meas.R, sm.meas.R) and sm.meas.fov_range == model.meas.fov_range
        assert (sm.pd, sm.clutter_rate, sm.log_rho) == (model.pd, model.clutter_rate, model.log_rho)
