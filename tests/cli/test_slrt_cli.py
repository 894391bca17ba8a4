"""`motionsig slrt`: outputs, figures, reproducibility, help, and bad input named by its option."""

import numpy as np
import pytest

from motionsig_cli.detection.track_existence import FUSION_METHODS
from motionsig_cli.experiments import slrt as exp
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
    assert set(t.column("method")) == {"ckf", "dkf", "lkf"}
    assert len(t.rows) == 4 * 3 * 10
    assert t.meta["sprt"]["log_B"] == pytest.approx(6.802, abs=1e-3)
    mean = t.numeric("mean_loglr")
    case = t.column("case")
    assert all(m < 0 for m, c in zip(mean, case, strict=True) if c == "no target")
    assert "mean log LR at scan 10" in err


def test_decisions_view_and_seed(capsys, tmp_path):
    args = ("slrt", "--view", "decisions", "--runs", "10", "--scans", "8", "--pd", "0.9", "--seed", "3", "-q")
    rc, out1, _ = run(capsys, *args)
    _, out2, _ = run(capsys, *args)
    assert rc == 0 and out1 == out2
    t = table(out1, tmp_path)
    frac = t.numeric("confirmed") + t.numeric("deleted") + t.numeric("undecided")
    np.testing.assert_allclose(frac, 1.0)
    assert set(t.column("case")) == {"target, p_D = 0.9", "no target"}


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
    # p_D = 1 and a sensor that sees nothing: the target hypothesis is impossible, log LR = -inf (never NaN)
    rc, out, _ = run(capsys, "slrt", "--filter-pd", "1", "--clutter", "0", "--pd", "0.9", "--runs", "3",
                     "--scans", "4", "--methods", "ckf", "-q")  # fmt: skip
    t = table(out, tmp_path, "b.csv")
    nt = [v for v, c in zip(t.column("mean_loglr"), t.column("case"), strict=True) if c == "no target"]
    assert rc == 0 and set(nt) == {"-inf"} and "clutter_floor" in t.meta


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
