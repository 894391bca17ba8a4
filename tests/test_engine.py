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
    (tmp_path / "ck" / "task-0000002.task").unlink()
    CALLS.clear()
    again = run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    assert CALLS == [6]  # only task 2 ran again
    assert np.concatenate(again).tobytes() == np.concatenate(full).tobytes()


def test_consume_takes_each_result_in_task_order_and_drops_it(many_tasks, tmp_path):
    """consume: every result once, in task order, whatever the workers; the list returned keeps none of them;
    resuming from a checkpoint hands over the stored results (read back one at a time) with the new ones."""
    tasks = tasks_of(23, 3)
    fn = functools.partial(_draws, 2.0)
    want = run_tasks(fn, tasks, Engine(1))
    for engine in (Engine(1), Engine(2)):
        got: list[tuple[int, np.ndarray]] = []
        kept = run_tasks(fn, tasks, engine, consume=lambda i, r: got.append((i, r)))  # noqa: B023
        assert [i for i, _ in got] == list(range(len(tasks))) and kept == [None] * len(tasks)
        assert np.concatenate([r for _, r in got]).tobytes() == np.concatenate(want).tobytes()
    ident = {"command": "test", "n": 23}
    run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    (tmp_path / "ck" / "task-0000003.task").unlink()
    got = []
    CALLS.clear()
    run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident, consume=lambda i, r: got.append((i, r)))
    assert CALLS == [9] and [i for i, _ in got] == list(range(len(tasks)))
    assert np.concatenate([r for _, r in got]).tobytes() == np.concatenate(want).tobytes()


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
    (tmp_path / "task-0000001.task").write_bytes((tmp_path / "task-0000000.task").read_bytes())
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


# ------------------------------------------------------------------ failures and interrupts of a pool run
def _fail(parent: int, how: str, where: str, trials: range) -> int:
    """A task that fails as ``how`` in the parent (``where="parent"``) or in a pool worker, from task 2 on."""
    import os
    import signal

    time.sleep(0.05)
    if (os.getpid() == parent) == (where == "parent") and trials.start >= 2:
        if how == "exit":
            os._exit(3)
        if how == "kill":
            os.kill(os.getpid(), signal.SIGKILL)
        if how == "memory":
            raise MemoryError("no memory left")
        raise ValueError(f"task {trials.start} failed")
    return trials.start


def _spawned(psutil) -> list:
    """This process's pool workers (and a LocalCluster's processes): children started by multiprocessing."""
    return [c for c in psutil.Process().children(recursive=True) if "spawn_main" in " ".join(c.cmdline())]


@pytest.mark.parametrize(
    ("how", "where", "error"),
    [
        ("exit", "worker", eng.WorkerDied),
        ("kill", "worker", eng.WorkerDied),
        ("memory", "worker", MemoryError),
        ("value", "worker", ValueError),
        ("memory", "parent", MemoryError),
        ("value", "parent", ValueError),
    ],
)
def test_a_failing_task_or_a_dead_worker_stops_a_pool_run_with_one_error(how, where, error):
    """A worker that dies (os._exit, SIGKILL as the OOM killer sends) or a task that raises, in a worker or in
    this process's own share: the run raises one error at once and leaves no worker behind."""
    import os

    psutil = pytest.importorskip("psutil")
    fn = functools.partial(_fail, os.getpid(), how, where)
    before = {c.pid for c in _spawned(psutil)}  # a session's Dask cluster (the dask_address fixture) stays
    t0 = time.perf_counter()
    with pytest.raises(error) as exc:
        run_tasks(fn, tasks_of(60, 1), Engine(3))  # 3 s of tasks: this process and 2 workers share them
    assert time.perf_counter() - t0 < 60
    if error is ValueError:
        assert str(exc.value).startswith("task ")
    _, alive = psutil.wait_procs([c for c in _spawned(psutil) if c.pid not in before], timeout=10)
    assert not alive


def test_a_task_whose_dask_workers_die_is_one_clear_error():
    """A task that kills every Dask worker it runs on (os._exit): Dask retries it on a fresh worker until it
    has lost ``allowed-failures`` + 1 of them (0 here), then the run raises WorkerDied. (The job used to be
    scattered: data lost with its workers, and the run failed with "Futures cancelled: already forgotten".)"""
    import os

    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    fn = functools.partial(_fail, os.getpid(), "exit", "worker")
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), pytest.raises(eng.WorkerDied):
        run_tasks(fn, tasks_of(200, 1), Engine(2, "local"))  # 10 s of tasks: the cluster gets some


def test_tiny_tasks_never_start_a_pool(monkeypatch):
    """200 tasks that take no time: this process computes them all before the pool would start (0.3 s)."""
    monkeypatch.delenv("MOTIONSIG_POOL_MIN_SECONDS", raising=False)

    def no_pool(*args, **kwargs):
        raise AssertionError("a pool was started")

    monkeypatch.setattr(eng, "ProcessPoolExecutor", no_pool)
    assert run_tasks(_pid, tasks_of(200, 1), Engine(2)) == [_pid(range(0))] * 200


def _pid_and_draw(trials: range) -> tuple[int, float]:
    import os

    time.sleep(0.1)
    return os.getpid(), float(trial_rng(5, trials.start).standard_normal())


def test_checkpoint_resume_with_2_workers_including_tasks_done_here(tmp_path, monkeypatch):
    """This process computes tasks beside its pool: a checkpoint holds tasks of both, and a resume with 2
    workers after deleting some of each gives the results of one uninterrupted worker."""
    import os

    monkeypatch.delenv("MOTIONSIG_POOL_MIN_SECONDS", raising=False)
    tasks, ident, ck = tasks_of(40, 1), {"command": "pids"}, tmp_path / "ck"
    first = run_tasks(_pid_and_draw, tasks, Engine(2, None, ck), identity=ident)
    here = [i for i, (pid, _) in enumerate(first) if pid == os.getpid()]
    there = [i for i, (pid, _) in enumerate(first) if pid != os.getpid()]
    assert here and there, "the run did not share its tasks between this process and the pool"
    for i in here[-2:] + there[-2:]:
        (ck / f"task-{i:07d}.task").unlink()
    again = run_tasks(_pid_and_draw, tasks, Engine(2, None, ck), identity=ident)
    plain = run_tasks(_pid_and_draw, tasks, Engine(1))
    assert [d for _, d in again] == [d for _, d in plain]
    assert [p for p, _ in again][: min(here[-2:] + there[-2:])] == [p for p, _ in first][
        : min(here[-2:] + there[-2:])
    ]


def _interrupt(parent: int, phase: str, n: int, trials: range) -> int:
    """A task that sends SIGINT (a terminal's Ctrl-C) to ``parent`` at ``phase``: ``first`` (this process's
    first task, before a pool or cluster is up), ``starting`` (this process's first task once pool processes
    exist, while they import), ``mid`` (the first task a worker runs), ``last`` (the last task)."""
    import multiprocessing
    import os
    import signal

    time.sleep(0.05)
    here = os.getpid() == parent
    fire = {
        "first": here and trials.start == 0,
        "starting": here and bool(multiprocessing.active_children()),
        "mid": not here,
        "last": trials.start == n - 1,
    }[phase]
    if fire:
        os.kill(parent, signal.SIGINT)
        time.sleep(0.5)
    return trials.start


INTERRUPT_SCRIPT = """
import functools, os, sys, time
import psutil
from motionsig_cli.engine import Engine, run_tasks, tasks_of
from tests.test_engine import _interrupt

scheduler = sys.argv[1] if sys.argv[1] != "pool" else None
for phase in sys.argv[2:]:
    n = 60 if phase == "last" else 400  # 400 × 50 ms: a loaded machine's cluster gets some of them
    t0 = time.perf_counter()
    try:
        run_tasks(functools.partial(_interrupt, os.getpid(), phase, n), tasks_of(n, 1), Engine(2, scheduler))
        print(phase, "finished")
    except KeyboardInterrupt:
        kids = [c for c in psutil.Process().children(recursive=True) if "spawn_main" in " ".join(c.cmdline())]
        _, alive = psutil.wait_procs(kids, timeout=10)
        print(phase, "interrupted", len(alive), "left", round(time.perf_counter() - t0, 1), "s", flush=True)
"""


@pytest.mark.parametrize(
    ("scheduler", "phases"),
    [("pool", ["first", "starting", "mid", "last"]), ("local", ["first", "mid", "last"])],
)
def test_ctrl_c_at_every_phase_stops_the_run_and_its_processes(tmp_path, monkeypatch, scheduler, phases):
    """Ctrl-C before the pool (or a LocalCluster) is up, while its processes start, mid-run and during the last
    task: run_tasks raises KeyboardInterrupt (the command layer's exit 130) and no worker is left."""
    import subprocess

    pytest.importorskip("psutil")
    if scheduler == "local":
        pytest.importorskip("distributed")
    monkeypatch.delenv("MOTIONSIG_POOL_MIN_SECONDS", raising=False)
    proc = subprocess.run(
        [sys.executable, "-c", INTERRUPT_SCRIPT, scheduler, *phases],
        capture_output=True,
        text=True,
        timeout=300,
    )
    lines = proc.stdout.splitlines()
    assert proc.returncode == 0 and len(lines) == len(phases), (proc.stdout, proc.stderr[-2000:])
    for phase, line in zip(phases, lines, strict=True):
        assert line.startswith(f"{phase} interrupted 0 left"), (line, proc.stderr[-2000:])


def test_the_run_time_rule_divides_by_the_workers_and_names_the_ways_out():
    """check_run_time: the one-core estimate over the run's workers against the limit; --max-minutes raises the
    limit; a checkpoint lifts it for a Monte Carlo, not for a computation in this process (parallel=False)."""
    from motionsig_cli.config import ConfigError
    from motionsig_cli.engine import Budget, budget, check_run_time

    check_run_time("runs", 10, 500.0, 600.0)  # under the limit on one core
    with pytest.raises(ConfigError, match=r"17 min on one core; the limit is 10 min: fewer runs; or raise"):
        check_run_time("runs", 10, 1000.0, 600.0, also="fewer runs; or ")
    with budget(Budget(workers=2)):
        check_run_time("runs", 10, 1000.0, 600.0)  # 500 s on 2 workers
        with pytest.raises(
            ConfigError, match=r"17 min on one core; the limit is 10 min: raise the limit"
        ) as exc:
            check_run_time("runs", 10, 1000.0, 600.0, parallel=False)
        assert "--checkpoint" not in str(exc.value)
    with budget(Budget(workers=2)), pytest.raises(ConfigError, match=r"on one core, 17 min on 2 workers"):
        check_run_time("runs", 10, 2000.0, 600.0)
    with budget(Budget(max_minutes=20.0)):
        check_run_time("runs", 10, 1000.0, 600.0)
    with budget(Budget(checkpoint=True)):
        check_run_time("runs", 10, 1e9, 600.0)
        with pytest.raises(ConfigError):
            check_run_time("runs", 10, 1e9, 600.0, parallel=False)
    asked = []
    with budget(Budget(workers=lambda: asked.append(1) or 4)):
        check_run_time("runs", 10, 500.0, 600.0)
        assert (
            not asked
        )  # the workers (a remote scheduler's, say) are counted only when the limit is exceeded
        check_run_time("runs", 10, 2000.0, 600.0)
        assert asked


# ------------------------------------------------------------------ hostile checkpoint directories (issue 39)
class _Marker:
    """A pickle that would create a file when unpickled."""

    def __init__(self, path):
        self.path = str(path)

    def __reduce__(self):
        return (open, (self.path, "w"))


def _index_line(i: int, data: bytes, key: bytes = b"an attacker's key", run: bytes = b"") -> str:
    """An index line for ``data`` as a forger writes it: the right format, an HMAC under a key of theirs."""
    import hashlib
    import hmac
    import json

    mac = hmac.new(key, run + data, hashlib.sha256).hexdigest()
    return json.dumps({"task": i, "bytes": len(data), "hmac": mac}) + "\n"


def test_a_forged_task_file_with_a_matching_index_line_cannot_change_a_result(tmp_path):
    """The issue's case: numbers changed in a task file and its index line rewritten to match (size, and a
    digest the forger can compute: SHA-256 or an HMAC under any key but the account's). The task is
    recomputed; the result is that of a clean run. A genuine file copied from another run of other
    parameters (same chunking, same key) is recomputed too: the run's manifest is in the HMAC."""
    import hashlib
    import json

    from motionsig_cli.taskdata import decode, encode

    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(6, 2)
    ident = {"command": "a"}
    full = run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    path = tmp_path / "ck" / "task-0000001.task"
    key, result = decode(path.read_bytes())
    forged = encode(key, result * 0 + 42.0)
    path.write_bytes(forged)
    sha_line = json.dumps({"task": 1, "bytes": len(forged), "sha256": hashlib.sha256(forged).hexdigest()})
    with open(tmp_path / "ck" / "tasks.jsonl", "a") as fh:
        fh.write(sha_line + "\n" + _index_line(1, forged))
    CALLS.clear()
    again = run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    assert CALLS == [2]
    assert np.concatenate(again).tobytes() == np.concatenate(full).tobytes()
    # a genuine task file (and its index line) of another run, of other parameters
    other = run_tasks(
        functools.partial(_draws, 2.0), tasks, Engine(1, None, tmp_path / "o"), identity={"command": "b"}
    )
    (tmp_path / "ck" / "task-0000002.task").write_bytes((tmp_path / "o" / "task-0000002.task").read_bytes())
    lines = (tmp_path / "o" / "tasks.jsonl").read_text().splitlines()
    with open(tmp_path / "ck" / "tasks.jsonl", "a") as fh:
        fh.write(next(line for line in lines if json.loads(line)["task"] == 2) + "\n")
    CALLS.clear()
    again = run_tasks(fn, tasks, Engine(1, None, tmp_path / "ck"), identity=ident)
    assert CALLS == [4]
    assert (
        np.concatenate(again).tobytes() == np.concatenate(full).tobytes() != np.concatenate(other).tobytes()
    )


def test_a_checkpoint_of_another_key_is_recomputed_and_one_of_the_same_key_resumes(tmp_path, monkeypatch):
    """The account's key signs; MOTIONSIG_CHECKPOINT_KEY shares a checkpoint between accounts."""
    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(6, 2)
    ident = {"command": "a"}
    monkeypatch.setenv("MOTIONSIG_CHECKPOINT_KEY", "the cluster's key")
    full = run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    CALLS.clear()
    run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    assert CALLS == []  # same key: every task resumed
    monkeypatch.setenv("MOTIONSIG_CHECKPOINT_KEY", "another account's key")
    again = run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    assert sorted(CALLS) == [0, 2, 4]  # another key: every task recomputed
    assert np.concatenate(again).tobytes() == np.concatenate(full).tobytes()


def test_a_crafted_pickle_in_a_checkpoint_never_runs(tmp_path):
    """A pickle under the old name and under the new one, with a forged index entry that matches it: never
    unpickled (the marker file never appears), the task recomputed, the result that of a clean run."""
    import pickle

    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(6, 2)
    ident = {"command": "a"}
    ck = tmp_path / "ck"
    clean = run_tasks(fn, tasks, Engine(1), identity=ident)
    run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    marker = tmp_path / "marker"
    bomb = pickle.dumps(("range(0, 2)", _Marker(marker)))
    (ck / "task-0000000.pkl").write_bytes(bomb)
    (ck / "task-0000000.task").write_bytes(bomb)
    with open(ck / "tasks.jsonl", "a") as fh:
        fh.write(_index_line(0, bomb))
    CALLS.clear()
    again = run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    assert not marker.exists()
    assert CALLS == [0]
    assert np.concatenate(again).tobytes() == np.concatenate(clean).tobytes()


def test_an_altered_task_file_is_detected_and_recomputed(tmp_path, caplog):
    """Numbers changed in a task file (its size kept): the digest differs from the index's, so the task is
    recomputed, counted and reported in one warning; the result is that of an uninterrupted run."""
    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(6, 2)
    ident = {"command": "a"}
    full = run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    path = tmp_path / "task-0000001.task"
    data = bytearray(path.read_bytes())
    data[-1] ^= 0x40  # the last byte of the last float
    path.write_bytes(bytes(data))
    CALLS.clear()
    with caplog.at_level("WARNING", logger="motionsig_cli.engine"):
        again = run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    assert CALLS == [2]
    assert np.concatenate(again).tobytes() == np.concatenate(full).tobytes()
    assert "1 task file(s) did not match" in caplog.text and "task-0000001.task" in caplog.text
    CALLS.clear()
    run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    assert CALLS == []  # the recomputed file is in the index: used from now on


def test_an_oversized_task_file_is_not_read(tmp_path, monkeypatch):
    """A file over the size limit, with a matching forged index entry, is recomputed without being read."""
    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(4, 2)
    ident = {"command": "a"}
    run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    big = b"\0" * 4096
    (tmp_path / "task-0000000.task").write_bytes(big)
    with open(tmp_path / "tasks.jsonl", "a") as fh:
        fh.write(_index_line(0, big))
    monkeypatch.setattr(eng, "MAX_TASK_BYTES", 1024)
    import motionsig_cli.tables as tables

    read, real = [], tables.read_regular
    monkeypatch.setattr(tables, "read_regular", lambda *a, **k: read.append(a) or real(*a, **k))
    CALLS.clear()
    run_tasks(fn, tasks, Engine(1, None, tmp_path), identity=ident)
    assert 0 in CALLS and not any("task-0000000" in str(a[0]) for a in read)


def test_special_entries_in_a_checkpoint_are_refused_by_name(tmp_path):
    """A task file that is a directory or a FIFO, a manifest that is a FIFO or not a JSON object, a checkpoint
    of the pickle format: one EngineError naming the path, at once (no hang, no internal error)."""
    import json
    import os

    fn = functools.partial(_draws, 1.0)
    tasks = tasks_of(4, 2)
    ident = {"command": "a"}
    ck = tmp_path / "ck"
    run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    (ck / "task-0000000.task").unlink()
    (ck / "task-0000000.task").mkdir()
    with pytest.raises(EngineError, match=r"task-0000000\.task is not a regular file"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    (ck / "task-0000000.task").rmdir()
    os.mkfifo(ck / "task-0000000.task")
    with pytest.raises(EngineError, match=r"task-0000000\.task is not a regular file"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    (ck / "task-0000000.task").unlink()
    outside = tmp_path / "outside.txt"
    outside.write_text("mine\n")
    index = ck / "tasks.jsonl"
    kept = index.read_bytes()
    index.unlink()
    index.symlink_to(outside)  # the run must not append to a file outside the checkpoint
    with pytest.raises(EngineError, match=r"tasks\.jsonl: is a symbolic link"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    assert outside.read_text() == "mine\n"
    index.unlink()
    index.write_bytes(kept)
    manifest = ck / "manifest.json"
    text = manifest.read_text()
    manifest.unlink()
    os.mkfifo(manifest)
    with pytest.raises(EngineError, match=r"manifest\.json: is a FIFO"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    manifest.unlink()
    manifest.write_text("[1, 2]")
    with pytest.raises(EngineError, match="not a JSON object"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    manifest.write_text("[" * 100_000)
    with pytest.raises(EngineError, match="unreadable manifest"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
    manifest.write_text(json.dumps({**json.loads(text), "version": 1}))
    with pytest.raises(EngineError, match=r"format version 1 .*pickled task files, which are never read"):
        run_tasks(fn, tasks, Engine(1, None, ck), identity=ident)
