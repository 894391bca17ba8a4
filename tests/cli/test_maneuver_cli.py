"""``motionsig maneuver``: views, the measurement pipe, reproducibility and bad input."""

import numpy as np

from motionsig_cli.engine import Engine
from motionsig_cli.experiments import maneuver as ex
from tests.cli.helpers import (
    bad_engine_options_test,
    checkpoint_resume,
    engine_outputs,
    one_line_error,
    run,
    table,
)

SMALL = ("--runs", "4", "--scans", "240")


def test_scans_view_and_figures(capsys, tmp_path):
    png, cmp_ = tmp_path / "f.png", tmp_path / "c.svg"
    rc, out, err = run(capsys, "maneuver", *SMALL, "--method", "imm,glr", "--plot", str(png),
                       "--plot-compare", str(cmp_))  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.meta["methods"] == ["imm", "glr"] and t.meta["sigma"] == [100.0, 200.0]
    assert len(t.rows) == 2 * 2 * (240 - 2)
    mu = np.array(
        [[float(r[t.columns.index(c)]) for c in ("mu_1", "mu_2", "mu_3")] for r in t.rows if r[1] == "imm"]
    )
    np.testing.assert_allclose(mu.sum(axis=1), 1.0, atol=1e-9)
    assert all(r[t.columns.index("mu_1")] == "" for r in t.rows if r[1] == "glr")
    assert png.stat().st_size > 10_000 and cmp_.stat().st_size > 10_000
    # the table equals the experiment layer's numbers
    sc = ex.ManeuverScenario(scans=240)
    ref = ex.monte_carlo(sc, 200.0, 4, 2008, ("imm",), ex.TrackerConfig())["imm"].stats
    rows = [r for r in t.rows if r[0] == "200.0" and r[1] == "imm"]
    np.testing.assert_allclose([float(r[t.columns.index("sd_x")]) for r in rows], ref.sd[:, 0], rtol=1e-12)


def test_summary_and_events_views(capsys, tmp_path):
    rc, out, err = run(capsys, "maneuver", "--runs", "6", "--scans", "340", "--method", "all", "--view", "summary",
                       "--sigma", "100")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    assert [r[1] for r in t.rows] == ["imm", "glr", "mlr", "cv"]
    assert {"rms_cruise", "rms_turn1", "false_alarms_per_1000", "detected_200", "delay_330"} <= set(t.columns)
    rc, out, err = run(capsys, "maneuver", "--runs", "6", "--scans", "340", "--method", "glr", "--view", "events",
                       "--sigma", "100")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path, "e.csv")
    assert [int(r[2]) for r in t.rows] == [200, 300, 305, 330]
    assert float(t.rows[0][t.columns.index("detected")]) == 1.0


def test_same_seed_same_bytes_and_seed_changes_result(capsys):
    args = ("maneuver", *SMALL, "--method", "glr", "--sigma", "150")
    a, b = run(capsys, *args)[1], run(capsys, *args)[1]
    c = run(capsys, *args, "--seed", "7")[1]
    assert a == b and a != c


def test_measurements_pipe_into_input(capsys, tmp_path, monkeypatch):
    """A simulated record written as CSV and tracked with --input gives run 0's Monte Carlo estimates."""
    rc, out, err = run(capsys, "maneuver", "--view", "measurements", "--runs", "1", "--sigma", "100",
                       "--scans", "260", "--preset", "turn90")  # fmt: skip
    assert rc == 0, err
    rec = tmp_path / "rec.csv"
    rec.write_text(out)
    rc, out, err = run(capsys, "maneuver", "--input", str(rec), "--method", "imm,glr")
    assert rc == 0, err
    t = table(out, tmp_path, "track.csv")
    assert t.meta["sigma"] == 100.0 and t.meta["T"] == 1.0
    sc = ex.ManeuverScenario("turn90", scans=260)
    z = ex.measurements(sc, 100.0, [0], 2008)
    for m in ("imm", "glr"):
        ref = ex.track(m, z, 1.0, 100.0, ex.TrackerConfig())
        rows = [r for r in t.rows if r[0] == m]
        xs = np.array([[float(r[t.columns.index("x")]), float(r[t.columns.index("y")])] for r in rows])
        np.testing.assert_allclose(xs, ref.pos[0], rtol=1e-12)
        assert int(rows[0][1]) == 3
    glr_rows = [r for r in t.rows if r[0] == "glr" and r[t.columns.index("declared")] == "true"]
    assert glr_rows and 195 <= int(glr_rows[0][t.columns.index("onset")]) <= 205


def test_record_without_sigma_needs_the_option(capsys, tmp_path):
    p = tmp_path / "r.csv"
    p.write_text("scan,z_x,z_y\n1,0,0\n2,0,450\n3,0,900\n")
    rc, _, err = run(capsys, "maneuver", "--input", str(p))
    assert rc == 2 and "--sigma" in err
    rc, _out, err = run(capsys, "maneuver", "--input", str(p), "--sigma", "50")
    assert rc == 0, err


def test_input_is_not_overwritten_and_several_runs_are_refused(capsys, tmp_path):
    rc, out, _ = run(
        capsys, "maneuver", "--view", "measurements", "--runs", "2", "--sigma", "100", "--scans", "20"
    )
    rec = tmp_path / "two.csv"
    rec.write_text(out)
    rc, _, err = run(capsys, "maneuver", "--input", str(rec))
    assert rc == 2 and "several values of 'run'" in err
    one = tmp_path / "one.csv"
    one.write_text("# sigma: 100\nscan,z_x,z_y\n1,0,0\n2,0,450\n3,0,900\n")
    before = one.read_text()
    rc, _, err = run(capsys, "maneuver", "--input", str(one), "-o", str(one))
    assert rc == 2 and "--input file" in err and one.read_text() == before
    bad = tmp_path / "b.csv"
    bad.write_text("# sigma: true\nscan,z_x,z_y\n1,0,0\n2,0,450\n3,0,900\n")
    rc, _, err = run(capsys, "maneuver", "--input", str(bad))
    assert rc == 2 and "must be a number" in err


def test_undefined_statistics_are_empty_cells_and_svg_is_reproducible(capsys, tmp_path):
    rc, out, err = run(
        capsys, "maneuver", "--runs", "1", "--scans", "240", "--method", "glr", "--view", "summary"
    )
    assert rc == 0, err
    assert "nan" not in out
    a, b = tmp_path / "a.svg", tmp_path / "b.svg"
    for p in (a, b):
        assert run(capsys, "maneuver", "--runs", "2", "--scans", "220", "--plot", str(p))[0] == 0
    assert a.read_bytes() == b.read_bytes()


# ------------------------------------------------------------------ the Monte Carlo engine
ENGINE_ARGS = ("maneuver", "--runs", "3", "--scans", "215", "--method", "imm,glr", "--sigma", "100,150")


def test_same_bytes_on_one_worker_two_workers_and_dask(capsys, tmp_path, dask_address, many_tasks):
    outs = engine_outputs(capsys, tmp_path, dask_address, *ENGINE_ARGS)
    assert outs["w1"] == outs["w2"] == outs["dask"]
    assert b"workers" not in outs["w1"] and b"scheduler" not in outs["w1"]
    # under many_tasks each σ's 3 runs are 3 tasks: 2 σ -> 6 tasks, partial sums added in task order
    job = ex.ManeuverJob(
        ex.ManeuverScenario(scans=215), (100.0, 150.0), 3, 2008, ("imm", "glr"), ex.TrackerConfig()
    )
    assert job.runs_per_task() == 1 and len(job.tasks()) == 6


def test_chunking_depends_on_the_parameters_only(monkeypatch):
    monkeypatch.delenv("MOTIONSIG_MIN_TASK_SECONDS", raising=False)
    sc = ex.ManeuverScenario()
    job = ex.ManeuverJob(sc, (100.0, 200.0), 500, 1, ("imm",), ex.TrackerConfig())
    per_task = job.runs_per_task()
    assert 1 < per_task <= 250
    fixed = ex.cost(sc.scans, 0, ("imm",), 1)
    seconds = ex.cost(sc.scans, per_task, ("imm",), 1) - fixed
    assert seconds >= max(0.1, 4 * fixed) * (
        1 - 1e-9
    )  # >= 0.1 s and >= 4x the per-batch overhead (to rounding)
    tasks = job.tasks()
    for i in (0, 1):
        runs = [r for j, r in tasks if j == i]
        assert [t for r in runs for t in r] == list(range(500))
        assert all(len(r) == per_task for r in runs[:-1])
    # the library function on an engine: same numbers as in this process
    a = ex.monte_carlo(
        ex.ManeuverScenario(scans=210), 100.0, 3, 5, ("imm", "glr"), ex.TrackerConfig(), chunk=1
    )
    b = ex.monte_carlo(ex.ManeuverScenario(scans=210), 100.0, 3, 5, ("imm", "glr"), ex.TrackerConfig(), chunk=1,
                       engine=Engine(2))  # fmt: skip
    for m in ("imm", "glr"):
        np.testing.assert_array_equal(a[m].stats.sd, b[m].stats.sd)
        np.testing.assert_array_equal(a[m].track0, b[m].track0)
    np.testing.assert_array_equal(a["glr"].onset, b["glr"].onset)


def test_checkpoint_resumes_to_the_same_bytes_and_refuses_other_parameters(capsys, tmp_path, many_tasks):
    # an interrupted run: every other chunk missing (run 0's track among them)
    ck, n_tasks = checkpoint_resume(capsys, tmp_path, ENGINE_ARGS, slice(None, None, 2))
    assert n_tasks == 6
    # another view of the same Monte Carlo reuses the checkpoint (views are computed from the task results)
    rc, _, err = run(capsys, *ENGINE_ARGS, "--view", "summary", "-q", "--checkpoint", str(ck))
    assert rc == 0, err
    other = tmp_path / "other.csv"
    for args in (("--seed", "7"), ("--glr-threshold", "10")):
        err = one_line_error(capsys, *ENGINE_ARGS, *args, "-q", "--checkpoint", str(ck), "-o", str(other))
        assert "--checkpoint" in err
        assert not other.exists()


test_bad_engine_options = bad_engine_options_test(*ENGINE_ARGS)


def test_views_without_monte_carlo_ignore_the_engine_options(capsys, tmp_path):
    ck = tmp_path / "ck"
    rc, out, err = run(capsys, "maneuver", "--view", "measurements", "--runs", "1", "--scans", "5", "--sigma",
                       "100", "--workers", "2", "--checkpoint", str(ck))  # fmt: skip
    assert rc == 0, err
    assert not ck.exists()
    rec = tmp_path / "rec.csv"
    rec.write_text(out)
    rc, _, err = run(capsys, "maneuver", "--input", str(rec), "--workers", "2", "--checkpoint", str(ck))
    assert rc == 0, err
    assert not ck.exists()


def test_the_command_layer_copies_of_core_constants_agree():
    """The command module imports no NumPy, so it spells out a few of the core's values: they must agree."""
    from motionsig_cli.cli import maneuver as cli
    from motionsig_cli.detection.glr import CHI2_2_999, CONTINUATIONS, CORRECTIONS
    from motionsig_cli.models.motion import G2_FORMS

    assert cli.CHI2_2_999 == CHI2_2_999
    assert tuple(g.value for g in cli.G2) == G2_FORMS
    assert tuple(p.value for p in cli.Preset) == ex.PRESETS
    assert tuple(v.value for v in cli.View) == (*ex.VIEWS, "measurements")
    assert tuple(c.value for c in cli.Correction) == CORRECTIONS
    assert tuple(c.value for c in cli.Continuation) == CONTINUATIONS
