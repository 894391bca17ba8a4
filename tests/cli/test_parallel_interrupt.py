"""Ctrl-C and SIGKILL of a Dask LocalCluster run: Ctrl-C leaves exit code 130, no output and a checkpoint
that a rerun resumes to the uninterrupted result, byte for byte; SIGKILL of the command leaves none of its
processes (the cluster's workers exit once their parent's pipe closes)."""

import contextlib
import os
import signal
import subprocess
import sys
import time

import pytest

pytest.importorskip("distributed")
psutil = pytest.importorskip("psutil")

# a small maneuver Monte Carlo cut into one task per run (MOTIONSIG_MIN_TASK_SECONDS), so that an
# interrupt falls between saved tasks
ARGS = ["maneuver", "--runs", "40", "--scans", "60", "-q"]
ENV = {**os.environ, "MOTIONSIG_MIN_TASK_SECONDS": "1e-9"}


def _motionsig(*args: str, **kw) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "motionsig_cli", *args], env=ENV, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, **kw)  # fmt: skip


def test_ctrl_c_of_a_local_cluster_run_resumes_from_its_checkpoint(tmp_path):
    ref, out, ck = tmp_path / "ref.csv", tmp_path / "out.csv", tmp_path / "ck"
    assert _motionsig(*ARGS, "--workers", "1", "-o", str(ref)).wait(timeout=120) == 0
    run = [*ARGS, "--scheduler", "local", "--workers", "2", "--checkpoint", str(ck), "-o", str(out)]
    proc = _motionsig(*run)
    try:
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline and len(list(ck.glob("task-*.task"))) < 3:
            time.sleep(0.05)
        saved = len(list(ck.glob("task-*.task")))
        assert 3 <= saved < 40, "the run did not save some of its tasks before the interrupt"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        with contextlib.suppress(Exception):
            proc.kill()
    assert proc.returncode == 130, err
    assert "interrupted after" in err and "--checkpoint" in err
    assert not out.exists()
    again = _motionsig(*run)
    _, err = again.communicate(timeout=120)
    assert again.returncode == 0, err
    assert out.read_bytes() == ref.read_bytes()


def test_local_cluster_processes_die_with_a_killed_parent(tmp_path):
    """SIGKILL (the OOM killer, a lost terminal) of a command running a LocalCluster: its workers, their
    helpers and the resource tracker exit within a few seconds; no output is written."""
    out = tmp_path / "out.csv"
    proc = _motionsig(
        "maneuver", "--runs", "3000", "--scheduler", "local", "--workers", "3", "-q", "-o", str(out)
    )  # 3 workers: this process and a LocalCluster of 2
    children: list = []
    try:
        parent = psutil.Process(proc.pid)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            children = parent.children(recursive=True)
            if sum("spawn_main" in " ".join(c.cmdline()) for c in children) >= 2:
                break
            time.sleep(0.2)
        assert sum("spawn_main" in " ".join(c.cmdline()) for c in children) >= 2, "the cluster did not start"
        time.sleep(1.0)
        children = parent.children(recursive=True)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)
        _, alive = psutil.wait_procs(children, timeout=10)
        assert not alive, [p.cmdline() for p in alive]
        assert not out.exists()
    finally:  # a failing run must not leave its processes behind either
        for p in children:
            with contextlib.suppress(Exception):
                p.kill()
        with contextlib.suppress(Exception):
            proc.kill()


def test_a_killed_pool_worker_ends_the_command_with_one_line(tmp_path):
    """SIGKILL of a pool worker (what the OOM killer does) mid-run: exit code 1, one line naming what happened,
    no output and none of the command's processes left. (A Dask cluster retries the task on another worker;
    tests/test_engine.py checks the error once it gives up.)"""
    out = tmp_path / "out.csv"
    env = {k: v for k, v in os.environ.items() if not k.startswith("MOTIONSIG_")}  # default tasks and pool
    proc = subprocess.Popen(
        [sys.executable, "-m", "motionsig_cli", "detect", "--montecarlo", "--trials", "400", "--fr-list", "0.01",
         "--R-list", "1e-1,1e-3", "--workers", "2", "-q", "-o", str(out)],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    children: list = []
    try:
        parent = psutil.Process(proc.pid)
        deadline = time.monotonic() + 90
        workers: list = []
        while time.monotonic() < deadline and not workers:
            children = parent.children(recursive=True)
            workers = [c for c in children if "spawn_main" in " ".join(c.cmdline())]
            time.sleep(0.1)
        assert workers, "the pool did not start"
        time.sleep(1.0)
        children = parent.children(recursive=True)
        workers[0].kill()
        _, err = proc.communicate(timeout=120)
        assert proc.returncode == 1, err
        assert err.count("\n") == 1 and "a worker process died" in err and "Traceback" not in err, err
        assert not out.exists()
        _, alive = psutil.wait_procs(children, timeout=10)
        assert not alive, [p.cmdline() for p in alive]
    finally:
        for p in children:
            with contextlib.suppress(Exception):
                p.kill()
        with contextlib.suppress(Exception):
            proc.kill()
