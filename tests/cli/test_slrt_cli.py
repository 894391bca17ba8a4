"""`motionsig slrt`: outputs, figures, reproducibility, help, and bad input named by its option."""

import numpy as np
import pytest

from motionsig_cli.detection.track_existence import FUSION_METHODS
from motionsig_cli.existence import slrt as exp
from motionsig_cli.tables import read_table
from tests.cli.helpers import (
    bad_engine_options_test,
    checkpoint_resume,
    engine_outputs,
    one_line_error,
    run,
    table,
)


def test_curves_and_plots(capsys, tmp_path):
    png, scan = tmp_path / "s.png", tmp_path / "scan.png"
    rc, out, err = run(
        capsys, "slrt", "--runs", "8", "--scans", "10", "--plot", str(png), "--plot-scan", str(scan)
    )
    assert rc == 0 and png.stat().st_size > 20_000 and scan.stat().st_size > 10_000
    t = table(out, tmp_path)
    assert set(t.column("method")) == {"ckf", "fkf", "lkf"}
    assert len(t.rows) == 6 * 3 * 10  # three target cases, three no-target cases (one per p_D)
    assert t.meta["sprt"]["log_B"] == pytest.approx(6.802, abs=1e-3)
    mean = t.numeric("mean_loglr")
    case = t.column("case")
    scan = t.column("scan")
    false = [(m, k) for m, c, k in zip(mean, case, scan, strict=True) if c.startswith("no target")]
    # a false track starts at log LR 0 on scan 1, then falls
    assert {m for m, k in false if k == "1"} == {0.0}
    assert all(m < 0 for m, k in false if k != "1")
    assert "mean log LR at scan 10" in err


def test_decisions_view_and_seed(capsys, tmp_path):
    args = ("slrt", "--view", "decisions", "--runs", "10", "--scans", "8", "--pd", "0.9", "--seed", "3", "-q")
    rc, out1, _ = run(capsys, *args)
    _, out2, _ = run(capsys, *args)
    assert rc == 0 and out1 == out2
    t = table(out1, tmp_path)
    frac = t.numeric("confirmed") + t.numeric("deleted") + t.numeric("undecided")
    np.testing.assert_allclose(frac, 1.0)
    assert set(t.column("case")) == {"target, p_D = 0.9", "no target, p_D = 0.9"}


def test_help_spells_out_every_fusion_method(capsys):
    rc, out, _ = run(capsys, "slrt", "--help")
    text = " ".join(out.replace("│", " ").split())
    assert rc == 0
    for name, method in FUSION_METHODS.items():
        assert f"{name} ({method.abbreviation} = {method.title}" in text
    assert "federated relaxed-" in text and "spec" not in text


def test_stop_freezes_scores_and_pd_one_gives_minus_inf_not_nan(capsys, tmp_path):
    rc, out, _ = run(capsys, "slrt", "--stop", "--runs", "6", "--scans", "6", "--pd", "0.9", "-q")
    t = table(out, tmp_path)
    assert rc == 0 and t.meta["stop"] is True
    sel = [i for i, (c, m) in enumerate(zip(t.column("case"), t.column("method"), strict=True))
           if c == "target, p_D = 0.9" and m == "ckf"]  # fmt: skip
    mean = t.numeric("mean_loglr")[sel]
    assert np.all(mean == mean[0])  # every run decided at scan 1 and frozen there
    # p_D = 1 and a sensor that sees nothing: the target hypothesis is impossible, log LR = -inf (never NaN);
    # without clutter there is nothing to start a false track on, so the no-target case is refused
    rc, _, err = run(capsys, "slrt", "--filter-pd", "1", "--clutter", "0", "--pd", "0.9", "--runs", "3",
                     "--scans", "4", "--methods", "ckf", "-q")  # fmt: skip
    assert rc == 2 and "--clutter" in err and "false track" in err
    sc = exp.SlrtScenario(scans=4, clutter_rate=0.0, pd_true=0.3, pd_filter=1.0)
    scores, _ = exp.run(sc, 20, 1, ("ckf",))
    assert np.isneginf(scores["ckf"][:, -1]).any() and not np.isnan(scores["ckf"]).any()
    rc, out, _ = run(capsys, "slrt", "--clutter", "0", "--pd", "1", "--target-only", "--runs", "2", "--scans", "3",
                     "--methods", "ckf", "-q")  # fmt: skip
    assert rc == 0 and "clutter_floor" in table(out, tmp_path, "b.csv").meta


# ------------------------------------------------------------------ the Monte Carlo engine
ENGINE_ARGS = ("slrt", "--runs", "5", "--scans", "6", "--pd", "0.9", "--clutter", "2")


def test_same_bytes_on_one_worker_two_workers_and_dask(capsys, tmp_path, dask_address, many_tasks):
    outs = engine_outputs(capsys, tmp_path, dask_address, *ENGINE_ARGS)
    assert outs["w1"] == outs["w2"] == outs["dask"]
    assert b"workers" not in outs["w1"] and b"scheduler" not in outs["w1"]
    # under many_tasks each case's 5 runs are 5 tasks: 2 cases -> 10 tasks, reduced across chunks
    sc = exp.SlrtScenario(clutter_rate=2.0, scans=6)
    job = exp.SlrtJob((sc, sc), 5, 2008)
    assert job.runs_per_task() == 1 and len(job.tasks()) == 10


def test_chunking_depends_on_the_parameters_only(monkeypatch):
    monkeypatch.delenv("MOTIONSIG_MIN_TASK_SECONDS", raising=False)
    sc = exp.SlrtScenario()
    job = exp.SlrtJob((sc, exp.SlrtScenario(target=False)), 200, 1)
    per_task = job.runs_per_task()
    assert 1 < per_task < 200
    seconds = exp.cost(sc, per_task)[0] - exp.cost(sc, 0)[0]
    worth = max(0.1, 4 * exp.cost(sc, 0)[0]) * (
        1 - 1e-9
    )  # >= 0.1 s and >= 4x the batch overhead (to rounding)
    assert seconds >= worth
    tasks = job.tasks()
    assert [c for c, _ in tasks] == sorted(c for c, _ in tasks)
    for case in (0, 1):
        runs = [r for c, r in tasks if c == case]
        assert [t for r in runs for t in r] == list(range(200))
        assert all(len(r) == per_task for r in runs[:-1]) and 0 < len(runs[-1]) <= per_task


def test_checkpoint_resumes_to_the_same_bytes_and_refuses_other_parameters(capsys, tmp_path, many_tasks):
    # an interrupted run: some chunks missing
    ck, n_tasks = checkpoint_resume(capsys, tmp_path, ENGINE_ARGS, slice(1, None, 3))
    assert n_tasks == 10
    other = tmp_path / "other.csv"
    err = one_line_error(capsys, *ENGINE_ARGS, "--seed", "7", "-q", "--checkpoint", str(ck), "-o", str(other))
    assert "--checkpoint" in err and "seed" in err
    assert not other.exists()


test_bad_engine_options = bad_engine_options_test(*ENGINE_ARGS)


# ------------------------------------------------------------------ --input DETECTIONS --sensor-table SENSORS
def _per_scan(t, value):
    """(method, scan) → the value's text, of a one-case curves table or a one-track record table."""
    return {(m, k): v for m, k, v in zip(t.column("method"), t.column("scan"), t.column(value), strict=True)}


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_the_files_of_a_simulated_run_reproduce_its_scores_byte_for_byte(capsys, tmp_path, fmt):
    case = ("--pd", "0.7", "--clutter", "1", "--scans", "12", "--seed", "5")
    d, s, sim, got = (tmp_path / n for n in (f"d.{fmt}", "s.csv", "sim.csv", "in.csv"))
    for args, path in ((("--view", "detections", "--runs", "1", "-f", fmt), d), (("--view", "sensors"), s),
                       (("--runs", "1", "--target-only"), sim)):  # fmt: skip
        rc, _, err = run(capsys, "slrt", *case, *args, "-o", str(path))
        assert rc == 0, err
    rc, _, err = run(capsys, "slrt", "--input", str(d), "--sensor-table", str(s), "-o", str(got))
    assert rc == 0, err
    a, b = read_table(sim), read_table(got)
    want, have = _per_scan(a, "mean_loglr"), _per_scan(b, "log_lr")
    assert len(want) == 3 * 12 and have == want  # the same full-precision text: the same floats
    assert b.meta["init"]["rule"].startswith("the file's metadata 'init'")
    assert set(b.column("track")) == {"1"} and "4 sensor(s), 12 scans" in err


def test_views_of_a_run_write_input_files(capsys, tmp_path):
    rc, out, err = run(
        capsys, "slrt", "--view", "detections", "--runs", "1", "--scans", "3", "--clutter", "0.2"
    )
    t = table(out, tmp_path)
    assert rc == 0 and t.columns[:5] == ("scan", "time", "sensor", "range [m]", "bearing [rad]")
    assert t.meta["view"] == "detections" and len(t.meta["init"]) == 4 and t.meta["T"] == 1.0
    assert set(t.column("origin")) <= {"target", "clutter", ""} and "run 0 of 'target, p_D = 0.9'" in err
    rc, out, _ = run(capsys, "slrt", "--view", "sensors", "--meas", "cartesian", "-q")
    t = table(out, tmp_path, "s.csv")
    assert rc == 0 and t.columns == ("sensor", "x [m]", "y [m]", "sigma_xy [m]", "pd", "clutter", "fov [m]")
    assert t.column("sensor") == ["radar1", "radar2", "radar3", "radar4"]


def test_an_independent_record_is_confirmed_and_clutter_alone_is_not(capsys, tmp_path):
    from tests.existence.test_slrt_record import INIT_XVY, write_detections, write_sensors

    s = tmp_path / "radars.csv"
    write_sensors(s)
    init = ",".join(repr(v) for v in INIT_XVY)
    decisions = {}
    for name, target, seed in (("target", True, 1), ("clutter", False, 2)):
        d = tmp_path / f"{name}.csv"
        write_detections(d, seed, target=target)
        rc, out, err = run(capsys, "slrt", "--input", str(d), "--sensor-table", str(s), "--init", init,
                           "--view", "decisions")  # fmt: skip
        assert rc == 0, err
        t = table(out, tmp_path, f"{name}_out.csv")
        decisions[name] = dict(zip(t.column("method"), t.column("decision"), strict=True))
        assert t.meta["per_sensor_values"] is True and t.meta["T"] == 2.0
    assert decisions == {"target": dict.fromkeys(("ckf", "fkf", "lkf"), "confirmed"),
                         "clutter": dict.fromkeys(("ckf", "fkf", "lkf"), "deleted")}  # fmt: skip
    # without --init: one tentative track per detection of the first scan
    rc, out, err = run(capsys, "slrt", "--input", str(tmp_path / "target.csv"), "--sensor-table", str(s),
                       "--methods", "ckf", "--view", "decisions")  # fmt: skip
    t = table(out, tmp_path, "tracks.csv")
    assert rc == 0 and len(t.rows) > 3 and "confirmed" in t.column("decision") and "track(s): ckf:" in err
    assert t.meta["init"]["rule"].startswith("one tentative track per detection of scan 1")


def test_one_sensor_says_the_methods_coincide(capsys, tmp_path):
    from tests.existence.test_slrt_record import INIT_XVY, SENSORS, write_detections, write_sensors

    d, s = tmp_path / "d.csv", tmp_path / "s.csv"
    write_detections(d, 3, sensors=SENSORS[:1])
    write_sensors(s, SENSORS[:1])
    rc, out, err = run(capsys, "slrt", "--input", str(d), "--sensor-table", str(s), "--init",
                       ",".join(map(str, INIT_XVY)), "--methods", "ckf,fkf,fkf-feedback,lkf,ldf")  # fmt: skip
    t = table(out, tmp_path)
    assert rc == 0 and "the fusion rules coincide" in err and "coincide" in t.meta["single_sensor"]
    per = {m: [v for v, mm in zip(t.column("log_lr"), t.column("method"), strict=True) if mm == m]
           for m in ("ckf", "fkf", "fkf-feedback", "lkf", "ldf")}  # fmt: skip
    assert len(per["ckf"]) > 5 and per["ckf"] == per["fkf"] == per["fkf-feedback"] == per["lkf"]  # to the bit
    # LDF's log odds of one sensor's existence probability is its log LR, up to the rounding of logaddexp
    np.testing.assert_allclose(np.array(per["ldf"], float), np.array(per["ckf"], float), rtol=1e-9, atol=1e-9)


def test_input_from_stdin_with_columns_and_units_options(capsys, tmp_path, monkeypatch):
    import io
    import sys

    s = tmp_path / "s.csv"
    s.write_text("id,east,north,sr,sphi,pd,clutter,fov\nA,0,0,0.05,0.2,0.9,1,20\n")
    text = "ts,radar,rng,az\n0,A,1.0,10\n1,A,1.1,10\n2,A,,\n3,A,1.3,10\n"
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text.encode())))
    rc, out, err = run(capsys, "slrt", "--input", "-", "--sensor-table", str(s), "--init", "800,100,170,20",
                       "--columns", "time=ts,sensor=radar,range=rng,bearing=az",
                       "--sensor-columns", "sigma_r=sr,sigma_phi=sphi", "--units",
                       "range=km,bearing=deg,sigma_r=km,x=km,y=km,fov=km")  # fmt: skip
    t = table(out, tmp_path)
    assert rc == 0, err
    assert t.meta["detections"]["input"] == "<stdin>" and t.meta["sensors"][0]["fov_m"] == 20_000.0
    assert t.meta["sensors"][0]["sigma_r_m"] == 50.0
    assert [int(v) for v in t.column("detections")[:4]] == [1, 1, 0, 1]


SENSOR_TEXT = (
    "sensor,x,y,sigma_r,sigma_phi,pd,clutter,fov\nA,0,0,50,0.2,0.9,2,20000\nB,1e4,0,50,0.2,0.9,2,20000\n"
)
DET_TEXT = "time,sensor,range,bearing\n0,A,100,0.1\n1,B,100,0.1\n"


@pytest.mark.parametrize(
    ("dets", "sensors", "needle"),
    [
        ("time,sensor,range,bearing\n0,A,1,0\n0,Q,1,0\n", SENSOR_TEXT, "d.csv:3: column 'sensor': sensor 'Q'"),
        ("time,sensor,range\n0,A,1\n", SENSOR_TEXT, "d.csv:1: missing column 'bearing'"),
        ("time,sensor,range,bearing\n0,A,1,abc\n", SENSOR_TEXT, "d.csv:2: column 'bearing': 'abc' is not a number"),
        ("time,sensor,range,bearing\n1,A,1,0\n0,A,1,0\n", SENSOR_TEXT, "d.csv:3: column 'time': time goes backwards"),
        ("time,sensor,range,bearing\n0,A,1,0\n1,B,30000,0\n", SENSOR_TEXT,
         "d.csv:3: column 'range': range 30000 m is beyond the field of view"),
        ("time,sensor,range [yd],bearing\n0,A,1,0\n", SENSOR_TEXT, "d.csv:1: column 'range [yd]': unknown length unit"),
        ("", SENSOR_TEXT, "d.csv: no header row"),
        ("time,sensor,range,bearing\n", SENSOR_TEXT, "d.csv: no detections"),
        (DET_TEXT, SENSOR_TEXT + "A,5,5,50,0.2,0.9,2,20000\n", "s.csv:4: column 'sensor': sensor 'A' is listed twice"),
        (DET_TEXT, "", "s.csv: no header row"),
        ("time,sensor,range,bearing\n2026-05-01T00:00:00Z,A,1,0\n2026-05-01T00:00:01,A,1,0\n", SENSOR_TEXT,
         "d.csv:3: column 'time': mixes timestamps"),
    ],
)  # fmt: skip
def test_bad_records_are_one_line_naming_file_line_and_column(capsys, tmp_path, dets, sensors, needle):
    d, s, out = tmp_path / "d.csv", tmp_path / "s.csv", tmp_path / "out.csv"
    d.write_text(dets)
    s.write_text(sensors)
    err = one_line_error(capsys, "slrt", "--input", str(d), "--sensor-table", str(s), "-o", str(out))
    assert err.startswith("motionsig slrt: error: ") and needle in err, err
    assert not out.exists()


def test_a_record_over_the_row_limit_is_refused(capsys, tmp_path, monkeypatch):
    from dataclasses import replace

    from motionsig_cli.existence import slrt_record

    monkeypatch.setattr(slrt_record, "DETECTION_SPEC", replace(slrt_record.DETECTION_SPEC, max_rows=5))
    d, s = tmp_path / "d.csv", tmp_path / "s.csv"
    d.write_text("time,sensor,range,bearing\n" + "".join(f"{k},A,1,0\n" for k in range(6)))
    s.write_text(SENSOR_TEXT)
    err = one_line_error(capsys, "slrt", "--input", str(d), "--sensor-table", str(s))
    assert "d.csv:7: more than 5 data rows" in err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--pd", "0.5"), "--pd: does not apply with a detections FILE"),
        (("--runs", "3"), "--runs: does not apply with a detections FILE"),
        (("--target-only",), "--no-target/--target-only: does not apply with a detections FILE"),
        (("--workers", "2"), "--workers: does not apply with a detections FILE"),
        (("--view", "sensors"), "--view"),
        (("--plot-scan", "x.png"), "--plot-scan"),
        (("--init", "1,2,3"), "--init: [1.0, 2.0, 3.0] is not four numbers"),
        (("--init-sd", "0,1"), "--init-sd"),
        (("--units", "bearing=grad"), "--units: 'bearing=grad' is not an angle unit"),
        (("--units", "speed=m"), "--units: 'speed' is not a column of the detections or sensors"),
        (("--columns", "nope=x"), "--columns"),
        (("--sensor-columns", "nope=x"), "--sensor-columns"),
        (("--T", "0"), "--T"),
        (("--meas", "cartesian"), "missing column 'x'"),
    ],
)
def test_options_that_do_not_fit_an_input_are_one_line(capsys, tmp_path, args, needle):
    d, s = tmp_path / "d.csv", tmp_path / "s.csv"
    d.write_text(DET_TEXT)
    s.write_text(SENSOR_TEXT)
    err = one_line_error(capsys, "slrt", "--input", str(d), "--sensor-table", str(s), *args)
    assert needle in err, err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--sensor-table", "s.csv"), "--sensor-table: applies only with a detections FILE"),
        (("--init", "0,0,0,0"), "--init: applies only with a detections FILE"),
        (("--view", "detections", "--runs", "5"), "--runs: --view detections writes one run"),
        (("--view", "sensors", "--plot", "p.png"), "--plot: --view sensors draws no figure"),
        (("--input", "d.csv"), "--sensor-table: is needed with a detections FILE"),
        (("--input", "d.csv", "--sensor-table", "s.csv", "-o", "d.csv"), "--out: is the --input file"),
    ],
)
def test_input_options_without_input_and_view_options_are_one_line(
    capsys, tmp_path, monkeypatch, args, needle
):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "d.csv").write_text(DET_TEXT)
    (tmp_path / "s.csv").write_text(SENSOR_TEXT)
    err = one_line_error(capsys, "slrt", *args)
    assert needle in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.csv", "s.csv"]


def test_help_documents_the_input_files(capsys):
    rc, out, _ = run(capsys, "slrt", "--help")
    text = " ".join(out.replace("│", " ").split())
    assert rc == 0 and "--input" in text and "--sensor-table" in text and "--init-sd" in text
    assert "detected nothing there" in text and "outside its sensor's field of view is refused" in text


# ------------------------------------------------------------------ the agile target, the filters' q, the study view
def test_agile_options_map_to_the_scenario(capsys, tmp_path):
    rc, out, err = run(capsys, "slrt", "--target-motion", "cv,agile", "--pd", "0.9", "--scans", "12", "--runs", "3",
                       "--turn-rate-deg", "6,-9", "--turn-scans", "2-4,8-10", "--accel", "4", "--accel-scans",
                       "6", "--filter-q", "250", "--view", "study")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.meta["target_motions"] == ["cv", "agile"] and t.meta["scenario"]["filter_q"] == 250.0
    man = t.meta["maneuvers"]
    assert [(m["kind"], m["scans"]) for m in man] == [
        ("turn", [2, 4]),
        ("longitudinal", [6, 6]),
        ("turn", [8, 10]),
    ]
    assert [m.get("rate_deg_s", m.get("accel_m_s2")) for m in man] == [6.0, 4.0, -9.0]
    assert man[2]["speed_m_s"] == pytest.approx(158.114 + 4.0, abs=1e-3)  # after the one-scan +4 m/s²
    assert t.column("case")[:6:3] == ["target, p_D = 0.9", "agile target, p_D = 0.9"]
    assert t.column("motion")[:6:3] == ["cv", "agile"] and t.columns == exp.STUDY_COLUMNS


def test_the_agile_view_of_a_run_writes_the_turning_truth(capsys, tmp_path):
    # the detections file of one run: --filter-q changes nothing in it (only the filters), --turn-rate-deg does
    base = ("slrt", "--view", "detections", "--runs", "1", "--scans", "10", "--clutter", "0", "--pd", "0.9",
            "--target-motion", "agile", "--turn-scans", "1-10", "--accel-scans", "none", "--accel", "none")  # fmt: skip
    outs = {}
    for name, extra in (("a", ()), ("q", ("--filter-q", "900")), ("r", ("--turn-rate-deg", "3"))):
        rc, outs[name], err = run(
            capsys, *base, *(("--turn-rate-deg", "9") if name != "r" else ()), *extra, "-q"
        )
        assert rc == 0, err
    assert outs["a"].split("\n", 1)[1] == outs["q"].split("\n", 1)[1].replace(', "filter_q": 900.0', "")
    assert outs["a"] != outs["r"]


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--turn-rate-deg", "3"), "--turn-rate-deg: applies only with --target-motion agile"),
        (("--accel-scans", "3-4"), "--accel-scans: applies only with --target-motion agile"),
        (("--target-motion", "zigzag"), "--target-motion: 'zigzag' is not one of cv, agile"),
        (("--target-motion", "agile,agile"), "--target-motion"),
        (("--target-motion", "agile", "--scans", "8"), "--turn-scans: (1, 10) ends after the last scan (8)"),
        (("--target-motion", "agile", "--turn-scans", "1-5,x"), "--turn-scans: expected windows first-last"),
        (
            ("--target-motion", "agile", "--turn-rate-deg", "9"),
            "--turn-rate-deg: (9.0,) gives 1 value(s) for 2",
        ),
        (
            ("--target-motion", "agile", "--turn-rate-deg", "9,95"),
            "--turn-rate-deg: 95 is not in [-90, 90] deg/s",
        ),
        (("--target-motion", "agile", "--accel", "-45"), "--accel: (-45.0,) brings the noise-free speed to"),
        (
            ("--target-motion", "agile", "--accel-scans", "9-12"),
            "--accel-scans: (9, 12) shares scan 9 with a turn",
        ),
        (("--filter-q", "-1"), "--filter-q: -1 is not in [0, 1e+06]"),
        (("--gate-pg", "0"), "--gate-pg: 0 is not in (0, 1]"),
        (("--feedback-every", "3"), "--feedback-every: applies only with --methods including fkf-feedback"),
        (("--methods", "fkf-feedback", "--feedback-every", "0"), "--feedback-every: 0 is not in [1, 100000]"),
        (("--ldf-prior", "0.3"), "--ldf-prior: applies only with --methods including ldf"),
        (("--methods", "ldf", "--ldf-prior", "1"), "--ldf-prior: 1 is not in (0, 1)"),
        (
            ("--methods", "ldf", "--ldf-weights", "1,1"),
            "--ldf-weights: (1.0, 1.0) are 2 weights for 4 sensors",
        ),
        (("--methods", "ldf", "--ldf-weights", "1,a"), "--ldf-weights"),
        (("--methods", "ckf,dkf"), "--methods: 'dkf' is exact only for linear (cartesian) sensors"),
    ],
)
def test_bad_agile_and_fusion_options_are_one_line_naming_the_option(capsys, tmp_path, args, needle):
    out = tmp_path / "out.csv"
    err = one_line_error(capsys, "slrt", "--runs", "2", *args, "-o", str(out))
    assert err.startswith("motionsig slrt: error: ") and needle in err, err
    assert not out.exists()


def test_fusion_options_map_to_the_rules_and_the_metadata(capsys, tmp_path):
    args = ("slrt", "--runs", "4", "--scans", "6", "--pd", "0.5", "--target-only", "--view", "study", "-q")
    rc, out, _ = run(capsys, *args, "--methods", "fkf-feedback,ldf,naive", "--feedback-every", "2",
                     "--ldf-prior", "0.3", "--ldf-weights", "1,2,3,4", "--gate-pg", "0.999")  # fmt: skip
    t = table(out, tmp_path)
    assert rc == 0
    assert (t.meta["feedback_every"], t.meta["ldf_prior"], t.meta["ldf_weights"], t.meta["gate_pg"]) == (
        2, 0.3, [1.0, 2.0, 3.0, 4.0], 0.999)  # fmt: skip
    assert "reset" in t.meta["fkf-feedback"] and "P0 LR_s" in t.meta["ldf"]
    st = exp.SlrtStudy(exp.SlrtScenario(scans=6), pd=(0.5,), no_target=False, runs=4,
                       methods=("fkf-feedback", "ldf", "naive"), feedback_every=2, ldf_prior=0.3,
                       ldf_weights=(1.0, 2.0, 3.0, 4.0), gate_pg=0.999)  # fmt: skip
    from motionsig_cli.engine import run_job

    want = st.result(run_job(st.job())).table("study")
    i = exp.STUDY_COLUMNS.index("mean_loglr_last")
    assert t.numeric("mean_loglr_last").tolist() == [r[i] for r in want.rows]  # the same scores to the bit
    assert t.column("method") == ["fkf-feedback", "ldf", "naive"]


def test_the_study_view_of_the_default_is_the_decisions_view_plus_columns(capsys, tmp_path):
    args = ("slrt", "--runs", "12", "--scans", "8", "--seed", "4", "-q")
    _, a, _ = run(capsys, *args, "--view", "decisions")
    _, b, _ = run(capsys, *args, "--view", "study")
    d, s = table(a, tmp_path), table(b, tmp_path, "s.csv")
    for col in ("case", "method", "confirmed", "deleted", "undecided", "error_rate"):
        assert d.column(col) == s.column(col)
    for x, y in zip(s.column("asn"), d.column("mean_decision_scan"), strict=True):
        assert x == y == "" or float(x) == pytest.approx(float(y))  # empty: no row decided
    assert "target_motions" not in d.meta and "study" not in d.meta and "Clopper-Pearson" in s.meta["study"]


def test_oc_and_matched_views(capsys, tmp_path):
    args = ("slrt", "--runs", "4", "--scans", "5", "--pd", "0.5", "--methods", "ckf,lkf,naive", "--seed", "2", "-q")  # fmt: skip
    rc, out, _ = run(capsys, *args, "--view", "matched")
    t = table(out, tmp_path)
    assert rc == 0 and t.columns == exp.MATCHED_COLUMNS
    # naive is left out: its score uses the thresholds
    assert t.column("method") == ["ckf", "lkf"] * len(exp.MATCHED_RATES)
    assert "reference_false" in t.meta["matched"] and t.meta["oc_grid"]["log_B"][0] == 0.5
    rc, out, _ = run(capsys, *args, "--view", "oc")
    oc = table(out, tmp_path, "oc.csv")
    assert rc == 0 and len(oc.rows) == 2 * len(exp.OC_LOG_A) * len(exp.OC_LOG_B)
    assert set(oc.column("false_case")) == {"no target, p_D = 0.5"}
    st = exp.SlrtStudy(exp.SlrtScenario(scans=5), pd=(0.5,), runs=4, seed=2, methods=("ckf", "lkf", "naive"))
    from motionsig_cli.engine import run_job

    want = st.result(run_job(st.job())).table("oc")
    i = exp.OC_COLUMNS.index("false_confirmed")
    np.testing.assert_array_equal(oc.numeric("false_confirmed"), [r[i] for r in want.rows])
