"""``detect`` on the Monte Carlo engine: identical output for 1 worker, 2 workers and Dask, checkpoint
resume, Ctrl-C, bad engine input, ``--method fft`` and ``--calibrate``; every option range a configuration
checks is refused naming the option; the progress bar of a single record."""

import math
import os
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from motionsig_cli.detection.lmp import LMPConfig
from motionsig_cli.modesig.lmp1d import LmpJob, threshold_for
from tests.cli.helpers import MC_1D, engine_outputs, one_line_error, run, table

MC_2D = (
    "detect",
    "--montecarlo",
    "--example",
    "2d",
    "--trials",
    "2",
    "--anr-pairs",
    "3,4",
    "--horizons",
    "3",
)
CAL = ("detect", "--calibrate", "--method", "fft", "--trials", "20", "--null-trials", "40", "--pfa", "0.1",
       "--R-list", "1", "--horizons", "5,10")  # fmt: skip


def _tasks(job_kwargs, R_list, trials):
    return LmpJob(chips=np.ones((3, 31)), R_list=R_list, trials=trials, **job_kwargs).tasks()


@pytest.mark.parametrize(
    "args", [MC_1D, (*MC_1D, "--method", "fft"), MC_2D, CAL], ids=["bank", "fft", "radar", "calibrate"]
)
def test_output_is_byte_identical_for_1_and_2_workers_and_dask(
    capsys, tmp_path, dask_address, many_tasks, args
):
    outs = engine_outputs(capsys, tmp_path, dask_address, *args)
    assert outs["w1"] == outs["w2"] == outs["dask"]
    assert b"workers" not in outs["w1"] and b"scheduler" not in outs["w1"]


def test_the_runs_above_really_are_split_into_tasks(many_tasks):
    assert len(_tasks(dict(fr_list=(0.01, 0.1), horizons_s=(5.0, 10.0), seed=1), [1e-2, 1e-3], 6)) == 12


def test_default_chunks_are_worth_four_times_their_fixed_cost(monkeypatch):
    """A task is the smallest number of trials worth ≥ 4× its fixed cost (the bank's Riccati recursion, the FFT
    path's simulation loop) and ≥ 0.1 s, capped at 200 records in memory; the last task takes the rest."""
    monkeypatch.delenv("MOTIONSIG_MIN_TASK_SECONDS", raising=False)
    for kwargs, trials in [
        (dict(fr_list=(0.01,), horizons_s=(80.0,), seed=1), 450),
        (dict(fr_list=(0.01, 0.1, 1.0), horizons_s=(80.0,), seed=1), 100),
        (dict(fr_list=(0.01,), horizons_s=(80.0,), seed=1, method="fft", cfg=LMPConfig(Q_a=0.0)), 300),
        (dict(fr_list=(0.01,), horizons_s=(5.0,), seed=1, method="fft", cfg=LMPConfig(Q_a=0.0)), 300),
    ]:
        job = LmpJob(chips=np.ones((3, 31)), R_list=(1e-3,), trials=trials, **kwargs)
        fixed, per_trial = job.cost()
        sizes = [job.task_size(t) for t in job.tasks()]
        per = sizes[0]
        assert sum(sizes) == trials and all(n == per for n in sizes[:-1])
        cap = 200 // len(job.fr_list)
        worth = max(0.1, 4 * fixed)
        assert per == cap or (
            per * per_trial >= worth * (1 - 1e-9) and (per - 1) * per_trial < worth * (1 - 1e-9)
        )
        assert per <= cap


def test_checkpoint_resume_is_identical_and_foreign_checkpoints_are_refused(capsys, tmp_path, many_tasks):
    ck = tmp_path / "ck"
    rc, _, err = run(
        capsys, *MC_1D, "--workers", "1", "--checkpoint", str(ck), "-o", str(tmp_path / "a.csv"), "-q"
    )
    assert rc == 0, err
    files = sorted(ck.glob("task-*.task"))
    assert len(files) == 12
    for f in files[::3]:
        f.unlink()
    rc, _, err = run(
        capsys, *MC_1D, "--workers", "2", "--checkpoint", str(ck), "-o", str(tmp_path / "b.csv"), "-q"
    )
    assert rc == 0, err
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    rc, _, err = run(capsys, *MC_1D, "--seed", "9", "--checkpoint", str(ck), "-q")
    assert rc == 2
    assert err.count("\n") == 1 and "--checkpoint" in err and "seed" in err
    rc, _, err = run(capsys, *MC_2D, "--checkpoint", str(ck), "-q")
    assert rc == 2 and "another command" in err


def test_unreachable_scheduler_fails_fast_with_its_address(capsys, tmp_path):
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    s.close()
    t0 = time.perf_counter()
    rc, _, err = run(capsys, *MC_1D, "--scheduler", address, "-o", str(tmp_path / "x.csv"))
    assert rc == 2 and address in err and err.count("\n") == 1
    assert time.perf_counter() - t0 < 5
    assert not (tmp_path / "x.csv").exists()


@pytest.mark.parametrize(
    "engine", [("--workers", "2"), ("--scheduler", "local", "--workers", "2")], ids=["pool", "dask"]
)
def test_ctrl_c_stops_cleanly_and_the_checkpoint_resumes_to_the_same_result(tmp_path, engine):
    """SIGINT to the whole process group (what a terminal's Ctrl-C does) while 2 workers run: the workers
    (pool processes, or a LocalCluster's nanny workers) must not print tracebacks of their own."""
    args = ["detect", "--montecarlo", "--trials", "12", "--fr-list", "0.01", "--R-list", "1e-2,1e-3",
            "--horizons", "10,20", *engine]  # fmt: skip
    env = {**os.environ, "MOTIONSIG_MIN_TASK_SECONDS": "1e-9", "MOTIONSIG_POOL_MIN_SECONDS": "0"}
    ck = tmp_path / "ck"
    exe = [sys.executable, "-m", "motionsig_cli"]
    proc = subprocess.Popen(
        [*exe, *args, "--checkpoint", str(ck), "-o", "out.csv"], cwd=tmp_path, env=env,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )  # fmt: skip
    deadline = time.time() + 120
    while time.time() < deadline and len(list(ck.glob("task-*.task"))) < 2:
        time.sleep(0.05)
    assert len(list(ck.glob("task-*.task"))) >= 2, "no task finished"
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and err.strip().count("\n") == 0, err
    assert "interrupted after" in err and "--checkpoint" in err
    assert not (tmp_path / "out.csv").exists()
    assert not [p for p in tmp_path.iterdir() if p.name not in ("ck",)]  # no temporary or partial file
    done = len(list(ck.glob("task-*.task")))
    assert done < 24, "the run had finished before the interrupt; the test proves nothing"
    subprocess.run(
        [*exe, *args, "--checkpoint", str(ck), "-o", "resumed.csv", "-q"], cwd=tmp_path, env=env, check=True
    )
    subprocess.run(
        [*exe, *args, "--workers", "1", "-o", "plain.csv", "-q"], cwd=tmp_path, env=env, check=True
    )
    assert (tmp_path / "resumed.csv").read_bytes() == (tmp_path / "plain.csv").read_bytes()


@pytest.mark.parametrize(
    ("extra", "option", "word"),
    [
        (("--Qa", "1"), "--method", "Q_a = 0"),
        (("--center", "h0-noise"), "--method", "center"),
        (("--filter", "ukf"), "--method", "filter bank"),
    ],
)
def test_fft_refuses_what_it_does_not_implement(capsys, extra, option, word):
    rc, _, err = run(capsys, *MC_1D, "--method", "fft", *extra)
    assert rc == 2 and option in err and word in err and err.count("\n") == 1


def test_fft_on_a_record_finds_the_simulated_mode(capsys, tmp_path):
    rc, rec, err = run(capsys, "simulate", "--mode", "2", "--tau-chips", "5", "--R", "1e-3", "--seed", "3")
    assert rc == 0, err
    src = tmp_path / "rec.csv"
    src.write_text(rec)
    rc, out, err = run(capsys, "detect", str(src), "--method", "fft", "--horizons", "40")
    assert rc == 0, err
    t = table(out, tmp_path)
    row = dict(zip(t.columns, t.rows[-1], strict=True))
    assert float(row["mode_hat"]) == 2 and float(row["tau_hat_chips"]) == 5
    assert t.meta["method"] == "fft"


def test_radar_refuses_the_fft_path_and_calibration(capsys):
    for extra in (("--method", "fft"), ("--Qa", "0")):
        rc, _, err = run(capsys, *MC_2D, *extra)
        assert rc == 2 and "1d" in err


def test_calibrated_threshold_holds_its_false_alarm_rate_on_fresh_seeds(capsys, tmp_path):
    """Calibrate on seed 11 (n₁ null trials), then count exceedances among n₂ null maxima of seed 12.
    |P̂_FA − p| ≤ 4 √(p(1−p)(1/n₁ + 1/n₂)) + 1/n₁ (sampling error of both sets plus the order statistic's
    granularity)."""
    p, n1, n2 = 0.05, 1200, 1200
    rc, out, err = run(capsys, "detect", "--calibrate", "--method", "fft", "--trials", "10", "--null-trials", str(n1),
                       "--pfa", str(p), "--R-list", "1e-2", "--horizons", "10", "--seed", "11", "--workers", "1")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    row = dict(zip(t.columns, t.rows[0], strict=True))
    thr = float(row["threshold"])
    assert float(row["pfa_in_sample"]) <= p
    job = LmpJob(LMPConfig(Q_a=0.0), (0.01,), (1e-2,), (10.0,), n2, 12, False, "fft")
    null = job.run_task((1e-2, range(n2))).lam_max[0, :, 0]
    p_hat = float(np.mean(null > thr))
    assert abs(p_hat - p) <= 4 * math.sqrt(p * (1 - p) * (1 / n1 + 1 / n2)) + 1 / n1


def test_threshold_rule():
    x = np.arange(100.0)
    assert threshold_for(x, 0.05) == 94.0  # 5 values (95..99) above
    assert threshold_for(x, 0.001) == 99.0
    assert np.sum(x > threshold_for(x, 0.1)) == 10


def test_calibration_plot_and_columns(capsys, tmp_path):
    png = tmp_path / "roc.png"
    rc, out, err = run(capsys, *CAL, "--plot", str(png))
    assert rc == 0, err
    assert png.stat().st_size > 1000
    t = table(out, tmp_path)
    assert len(t.rows) == 2
    row = dict(zip(t.columns, t.rows[0], strict=True))
    assert float(row["pfa_in_sample"]) <= 0.1 and 0 <= float(row["pd"]) <= 1
    rc, _, err = run(capsys, *CAL, "--pfa", "1.5")
    assert rc == 2 and "--pfa" in err


@pytest.mark.parametrize(
    ("args", "option", "word"),
    [
        ((*MC_1D[:-2], "--horizons", "0.02"), "--horizons", "one sample"),
        (("detect", "--calibrate", "--method", "fft", "--pfa", "1e-9"), "--pfa", "null trials"),
        (
            ("detect", "--calibrate", "--method", "fft", "--null-trials", "3000000"),
            "--null-trials",
            "at most",
        ),
        (("detect", "--montecarlo", "--trials", "60000000", "--R-list", "1,2"), "--trials", "at most"),
    ],
)
def test_runaway_or_degenerate_sizes_are_refused_at_once(capsys, args, option, word):
    t0 = time.perf_counter()
    rc, out, err = run(capsys, *args)
    assert rc == 2 and out == "" and option in err and word in err and err.count("\n") == 1
    assert time.perf_counter() - t0 < 5


def test_fewer_null_trials_than_one_over_pfa_is_warned(capsys):
    rc, _, err = run(capsys, "detect", "--calibrate", "--method", "fft", "--trials", "2", "--null-trials", "5",
                     "--pfa", "0.01", "--R-list", "1", "--horizons", "2")  # fmt: skip
    assert rc == 0 and "warning" in err and "largest null maximum" in err


@pytest.fixture(scope="module")
def short_records(tmp_path_factory):
    """A 2 s 1-D record and a 2 s radar record."""
    from motionsig_cli.cli.app import main

    d = tmp_path_factory.mktemp("short")
    one, two = d / "one.csv", d / "two.csv"
    assert main(["simulate", "--duration", "2", "-q", "-o", str(one)]) == 0
    assert main(["simulate", "--example", "2d", "--duration", "2", "-q", "-o", str(two)]) == 0
    return one, two


@pytest.mark.parametrize(
    ("which", "extra", "option", "word"),
    [
        (0, ("--threshold", "nan"), "--threshold", "is not a number"),
        (0, ("--filter", "ukf", "--center", "h0-noise"), "--filter", "center none"),
        (0, ("--filter", "ukf", "--kappa=-4.5"), "--kappa", "n = 4 states"),
        (0, ("--horizons", "3"), "--horizons", "longer than the record"),
        (1, ("--horizons", "0"), "--horizons", "> 0"),
        (1, ("--alpha", "0"), "--alpha", "not a finite number > 0"),
    ],
)
def test_record_checks_are_reported_as_the_option(capsys, short_records, which, extra, option, word):
    err = one_line_error(capsys, "detect", str(short_records[which]), *extra)
    assert f"Invalid value for {option}: " in err and word in err, err


@pytest.mark.parametrize(("which", "extra"), [(0, ()), (0, ("--filter", "ukf")), (0, ("--center", "h0-noise")),
                                              (1, ()), (0, ("--method", "fft", "--Qa", "0"))])  # fmt: skip
def test_a_single_record_drives_a_progress_bar_to_its_total(capsys, monkeypatch, short_records, which, extra):
    """The bar of a single record gets the bank's total of time steps and is advanced to it exactly (in
    blocks of steps); the FFT path has no bank (total 0)."""
    import contextlib

    import motionsig_cli.cli.detect as cli_detect
    import motionsig_cli.cli.detect_radar as cli_radar

    bars = []

    @contextlib.contextmanager
    def fake_bar(label, total, quiet):
        done = []
        bars.append((label, total, done))
        yield done.append

    monkeypatch.setattr(cli_detect, "progress_bar", fake_bar)
    monkeypatch.setattr(cli_radar, "progress_bar", fake_bar)
    rc, _, err = run(capsys, "detect", str(short_records[which]), "-q", *extra)
    assert rc == 0, err
    ((label, total, done),) = bars
    n = 40  # 2 s at T = 0.05 s
    fft = "fft" in extra
    expected = 0 if fft else 3 * n if "h0-noise" in extra else 2 * n if which == 0 and not extra else n
    assert total == expected and sum(done) == total, (label, total, done)
    assert fft or len(done) >= 1
