"""The Monte Carlo engine: task order, chunking, checkpoints, scheduler errors (issue 9)."""

import contextlib
import functools
import socket
import sys
import time

import numpy as np
import pytest

from motionsig_cli import engine as eng
from motionsig_cli.engine import Engine, EngineError, run_tasks, split_address, tasks_of, trials_per_task
from motionsig_cli.rng import trial_rng

CALLS: list[int] = []


def _draws(scale: float, trials: range) -> np.ndarray:
    """A task: one normal draw per trial from the trial's own stream."""
    CALLS.append(trials.start)
    return np.array([scale * trial_rng(5, t).standard_normal() for t in trials])


def test_tasks_cover_the_trials_in_order():
    tasks = tasks_of(10, 4)
    assert [list(t) for t in tasks] == [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9]]
    with pytest.raises(ValueError):
        tasks_of(3, 0)


def test_chunks_are_worth_a_tenth_of_a_second(monkeypatch):
    monkeypatch.delenv("MOTIONSIG_MIN_TASK_SECONDS", raising=False)
    assert trials_per_task(0.03) == 4  # 4 × 0.03 s ≥ 0.1 s
    assert trials_per_task(0.5) == 1
    assert trials_per_task(1e-6, at_most=500) == 500
    monkeypatch.setenv("MOTIONSIG_MIN_TASK_SECONDS", "1e-9")
    assert trials_per_task(0.03) == 1


def test_results_are_in_task_order_whatever_the_workers(many_tasks):
    tasks = tasks_of(23, 3)
    fn = functools.partial(_draws, 2.0)
    one = np.concatenate(run_tasks(fn, tasks, Engine(1)))
    two = np.concatenate(run_tasks(fn, tasks, Engine(2)))
    assert one.tobytes() == two.tobytes()
    chunked = np.concatenate(run_tasks(fn, tasks_of(23, 7), Engine(1)))
    assert chunked.tobytes() == one.tobytes()  # per-trial streams: the chunking does not matter either


def test_progress_counts_trials():
    seen = []
    tasks = tasks_of(10, 4)
    run_tasks(
        functools.partial(_draws, 1.0), tasks, Engine(1), sizes=[len(t) for t in tasks], progress=seen.append
    )
    assert seen == [4, 4, 2]


def test_checkpoint_resumes_only_the_missing_tasks(tmp_path):
    tasks = tasks_of(12, 3)
    fn = functools.partial(_draws, 1.0)
    ident = {"command": "test", "n": 12}
    full = run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    (tmp_path / "ck" / "task-0000002.pkl").unlink()
    CALLS.clear()
    again = run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    assert CALLS == [6]  # only task 2 ran again
    assert np.concatenate(again).tobytes() == np.concatenate(full).tobytes()


def test_checkpoint_of_other_parameters_is_refused(tmp_path):
    fn = functools.partial(_draws, 1.0)
    run_tasks(fn, tasks_of(4, 2), Engine(1, None, tmp_path), identity={"command": "a", "seed": 1})
    with pytest.raises(EngineError, match=r"other parameters.*seed") as exc:
        run_tasks(fn, tasks_of(4, 2), Engine(1, None, tmp_path), identity={"command": "a", "seed": 2})
    assert exc.value.field == "checkpoint"
    with pytest.raises(EngineError, match="another command"):
        run_tasks(fn, tasks_of(4, 2), Engine(1, None, tmp_path), identity={"command": "b", "seed": 1})


def test_a_non_empty_directory_without_manifest_is_refused(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(EngineError, match="not empty"):
        run_tasks(
            functools.partial(_draws, 1.0),
            tasks_of(2, 1),
            Engine(1, None, tmp_path),
            identity={"command": "a"},
        )


@pytest.mark.parametrize("workers", [0, -1, 1.5, True])
def test_bad_worker_counts(workers):
    with pytest.raises(EngineError) as exc:
        Engine(workers)
    assert exc.value.field == "workers"


@pytest.mark.parametrize("address", ["nohost", "tcp://host", "http://a:1", "a:0", "a:99999", "   "])
def test_bad_scheduler_addresses(address):
    with pytest.raises(EngineError) as exc:
        Engine(1, address)
        split_address(address)
    assert exc.value.field == "scheduler"


def _closed_port() -> int:
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def test_unreachable_scheduler_fails_fast_naming_the_address():
    pytest.importorskip("distributed")
    address = f"tcp://127.0.0.1:{_closed_port()}"
    t0 = time.perf_counter()
    with pytest.raises(EngineError, match=address.replace(".", r"\.")):
        run_tasks(functools.partial(_draws, 1.0), tasks_of(4, 2), Engine(1, address))
    assert time.perf_counter() - t0 < 5.0


def test_without_dask_the_scheduler_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(EngineError, match=r"motionsig_cli\[dask\]"):
        run_tasks(functools.partial(_draws, 1.0), tasks_of(4, 2), Engine(1, "local"))


def test_dask_cluster_gives_the_same_results(dask_address):
    tasks = tasks_of(15, 2)
    fn = functools.partial(_draws, 3.0)
    local = np.concatenate(run_tasks(fn, tasks, Engine(1)))
    dask = np.concatenate(run_tasks(fn, tasks, Engine(1, dask_address)))
    assert local.tobytes() == dask.tobytes()


def test_min_task_seconds_env_is_validated(monkeypatch):
    monkeypatch.setenv("MOTIONSIG_MIN_TASK_SECONDS", "abc")
    assert eng.min_task_seconds() == eng.MIN_TASK_SECONDS
    monkeypatch.setenv("MOTIONSIG_MIN_TASK_SECONDS", "-1")
    assert eng.min_task_seconds() == eng.MIN_TASK_SECONDS


def test_a_small_run_stays_in_process_and_a_large_one_starts_the_pool(monkeypatch):
    """The first task is timed here; the pool starts only when the rest would take ≥ POOL_MIN_SECONDS."""
    import os

    tasks = tasks_of(6, 1)
    monkeypatch.delenv("MOTIONSIG_POOL_MIN_SECONDS", raising=False)
    pids = run_tasks(_pid, tasks, Engine(2))
    assert set(pids) == {os.getpid()}
    monkeypatch.setenv("MOTIONSIG_POOL_MIN_SECONDS", "0")
    pids = run_tasks(_pid, tasks, Engine(2))
    assert os.getpid() not in pids  # 0: no first task timed here, every task in the pool


def _pid(_: range) -> int:
    import os

    return os.getpid()


def test_a_checkpoint_of_other_chunk_boundaries_is_refused(tmp_path):
    """Same identity, same number of tasks, other boundaries: mixing them would drop or double trials."""
    fn = functools.partial(_draws, 1.0)
    ident = {"command": "a"}
    run_tasks(fn, [range(0, 5), range(5, 10)], Engine(1, None, tmp_path), identity=ident)
    with pytest.raises(EngineError, match="task_list_sha256"):
        run_tasks(fn, [range(0, 9), range(9, 10)], Engine(1, None, tmp_path), identity=ident)


def test_a_task_file_copied_from_another_task_is_recomputed(tmp_path):
    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(9, 3)
    ident = {"command": "a"}
    full = run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    (tmp_path / "task-0000001.pkl").write_bytes((tmp_path / "task-0000000.pkl").read_bytes())
    CALLS.clear()
    again = run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    assert CALLS == [3]
    assert np.concatenate(again).tobytes() == np.concatenate(full).tobytes()


def test_a_silent_server_is_not_taken_for_a_scheduler():
    """A port that accepts connections but sends no Dask handshake (an HTTP server waits for a request)."""
    pytest.importorskip("distributed")
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(4)
    address = f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    try:
        t0 = time.perf_counter()
        with pytest.raises(EngineError, match="no Dask handshake"):
            run_tasks(functools.partial(_draws, 1.0), tasks_of(4, 2), Engine(1, address, connect_timeout=0.5))
        assert time.perf_counter() - t0 < 3
    finally:
        srv.close()


def test_tls_addresses_are_refused():
    with pytest.raises(EngineError, match="TLS"):
        split_address("tls://10.0.0.1:8786")


# ------------------------------------------------------------------ the Monte Carlo job protocol
from dataclasses import dataclass as _dataclass  # noqa: E402

from motionsig_cli.engine import MonteCarloJob, job_trials, run_job  # noqa: E402


@_dataclass(frozen=True)
class _SquaresJob:
    """Sum of t² over trials 0..n−1, chunked 3 trials a task."""

    n: int
    name: str = "squares"

    def tasks(self) -> list[range]:
        return tasks_of(self.n, 3)

    def task_size(self, task: range) -> int:
        return len(task)

    def run_task(self, task: range) -> int:
        return sum(t * t for t in task)

    def reduce(self, tasks, results) -> int:
        return sum(results)

    def identity(self) -> dict:
        return {"n": self.n}


def test_run_job_runs_any_job_of_the_protocol(tmp_path):
    job = _SquaresJob(10)
    assert isinstance(job, MonteCarloJob)
    assert job_trials(job) == 10
    seen = []
    assert run_job(job, progress=seen.append) == sum(t * t for t in range(10))
    assert seen == [3, 3, 3, 1]
    # the job's name and identity make the checkpoint's manifest
    assert run_job(job, Engine(1, checkpoint=tmp_path / "ck")) == 285
    manifest = (tmp_path / "ck" / "manifest.json").read_text()
    assert '"command": "squares"' in manifest and '"n": 10' in manifest
    with pytest.raises(EngineError, match="other parameters"):
        run_job(_SquaresJob(11), Engine(1, checkpoint=tmp_path / "ck"))


def test_pool_workers_die_with_a_killed_parent(tmp_path):
    """SIGKILL of a 3-worker run (as the OOM killer or a lost terminal would) gives the parent no chance to stop
    its pool: the workers notice that they were re-parented and exit within a few seconds; no output is
    written."""
    import os
    import signal
    import subprocess

    psutil = pytest.importorskip("psutil")
    out = tmp_path / "out.csv"
    cmd = [sys.executable, "-m", "motionsig_cli", "detect", "--montecarlo", "--trials", "4000", "--fr-list", "0.01",
           "--R-list", "1e-1,1e-3", "--workers", "3", "-q", "-o", str(out)]  # fmt: skip
    # 3 workers: this process and 2 spawned ones
    parent = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers: list = []
    others: list = []
    try:
        proc = psutil.Process(parent.pid)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and len(workers) < 2:
            workers = [
                c for c in proc.children(recursive=True) if "multiprocessing.spawn" in " ".join(c.cmdline())
            ]
            time.sleep(0.2)
        assert len(workers) == 2, "the pool did not start"
        time.sleep(1.0)  # the workers are past their initializer
        others = [c for c in proc.children(recursive=True) if c not in workers]  # the resource tracker
        os.kill(parent.pid, signal.SIGKILL)
        parent.wait(timeout=10)
        _, alive = psutil.wait_procs([*workers, *others], timeout=10)
        assert not alive, [p.cmdline() for p in alive]
        assert not out.exists()
    finally:  # a failing run must not leave its processes behind either
        for p in [*workers, *others]:
            with contextlib.suppress(Exception):
                p.kill()
        with contextlib.suppress(Exception):
            parent.kill()
