"""One Monte Carlo engine for every command: in-process, a local process pool, or a Dask cluster.

A Monte Carlo run is a list of *tasks* (chunks of trials, each worth ≥ 0.1 s of work) and a pure,
picklable task function. Each trial draws only from its own ``SeedSequence(seed, spawn_key=(t, …))``
child (:mod:`motionsig_cli.rng`) and the chunking depends on the parameters only, never on the
number of workers; results come back **in task order** and are reduced in that order. So the
output of a command is byte-identical for 1 worker, N workers and a Dask cluster.

``checkpoint``: a directory that keeps every finished task's result (data, never a pickle:
:mod:`motionsig_cli.taskdata`; written atomically, its size and an HMAC-SHA256 under the account's
checkpoint key (:mod:`motionsig_cli.checkpoint_key`) in an index checked before use)
next to a manifest naming the command and its parameters. A rerun with the same directory loads
the finished tasks and runs only the others, so an interrupted sweep resumes to the result of an
uninterrupted one. A directory made by another command or parameter set is refused.

A local run of N workers is this process and N − 1 spawned ones: this process starts computing at once,
and the pool is spawned beside it only once it has computed for :data:`POOL_MIN_SECONDS` with tasks left,
so small runs never pay for a pool and a large one loses no time to its start-up. The job (the task
function) is sent to each worker once, when it starts; tasks go out one at a time, so no task waits
behind a busy worker while another is idle. Where a task runs never changes what it computes. A Dask
LocalCluster of N workers is the same: this process and N − 1 Dask workers.

A worker that dies (killed, out of memory) ends a local run with :class:`WorkerDied` (once this process has
finished the task it is computing); a Dask cluster retries the task on another worker first. A task's
exception, in a worker or here, is raised once, and the workers are stopped.

Every process of a run computes with one BLAS thread (:func:`one_blas_thread`), so a task's numbers never
depend on where it ran, and the processes do not fight over the cores. A process keeps what its tasks compute
before they read a record (a bank's Riccati recursion; :mod:`motionsig_cli.cache`), so small tasks cost no
more per trial than large ones.

Workers ignore SIGINT: Ctrl-C reaches the main process only, which cancels the pending tasks,
stops the workers and re-raises :class:`KeyboardInterrupt` (the command layer turns it into one
line and exit code 130; no output file is written before all tasks are done).
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib
import hmac
import json
import logging
import math
import multiprocessing
import os
import queue
import signal
import socket
import stat
import tempfile
import threading
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn, Protocol, TypeVar, runtime_checkable

from motionsig_cli.config import ConfigError, integer
from motionsig_cli.errors import InputError

R = TypeVar("R")

MIN_TASK_SECONDS = 0.1  # a task shorter than this costs more in scheduling than it computes
POOL_MIN_SECONDS = (
    0.1  # this process computes alone this long before a pool (~0.35 s of a core a worker) starts
)
MANIFEST = "manifest.json"
CHECKPOINT_VERSION = 2  # 1: pickled task files (never read: a pickle can run code)
TASK_INDEX = "tasks.jsonl"
"""The checkpoint's index: one line ``{"task": i, "bytes": n, "hmac": h}`` per task file written, h the
HMAC-SHA256 under the checkpoint key of the manifest's SHA-256 and the file's bytes."""
TASK_SUFFIX = ".task"
MAX_TASK_BYTES = 256 << 20
"""Largest task file written or read (a larger result is not kept; a larger file is recomputed)."""
MAX_MANIFEST_BYTES = 16 << 20
INDEX_LINE_BYTES = 200
_LOG = logging.getLogger("motionsig_cli.engine")
# Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536: glibc then returns freed memory at once,
# and numpy's large temporaries are mapped and unmapped on every step — the filter banks ran 3.3x slower
# in a Dask worker than in this process (2.25 s vs 0.68 s for 100 trials). Unset for our LocalCluster;
# workers of a remote cluster should be started without it (README).
TRIM_KEY = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"
DASK_EXTRA = "pip install 'motionsig_cli[dask]'  (installs dask and distributed)"


def default_workers() -> int:
    """The cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


class EngineError(ConfigError):
    """Bad engine input: ``field`` names the :class:`Engine` field to blame (``workers``, ``scheduler``,
    ``checkpoint``); the message says what is wrong with its value."""

    def __init__(self, field: str, message: str) -> None:
        ValueError.__init__(self, f"{field}: {message}")
        self.field = field
        self.value = None
        self.reason = message

    @property
    def detail(self) -> str:
        """The message without the field's name."""
        return self.reason


class WorkerDied(RuntimeError):
    """A worker process ended while it ran a task (killed, out of memory, ``os._exit``): the run stops.

    A local pool's lost worker ends the run at once (``__cause__``: the pool's ``BrokenProcessPool``);
    a Dask cluster retries a task whose worker died and gives up once it has lost that many workers
    (``distributed.scheduler.allowed-failures``; ``__cause__``: Dask's ``KilledWorker``).
    """


@dataclass(frozen=True, slots=True)
class Engine:
    """Where the tasks run.

    Attributes:
        workers: Local processes, this one included (1 = in this process); with ``scheduler="local"``
            the same: this process and ``workers − 1`` Dask workers of a LocalCluster (one for ``1``).
        scheduler: ``None`` (local process pool), ``"local"`` (a Dask LocalCluster on 127.0.0.1) or
            the address of a running Dask scheduler (``tcp://host:port`` or ``host:port``).
        checkpoint: Directory for finished task results (resume after an interruption).
        connect_timeout: Seconds to wait for a remote scheduler before giving up.

    Examples:
        >>> from motionsig_cli import Engine
        >>> Engine().workers  # one: in this process
        1
    """

    workers: int = 1
    scheduler: str | None = None
    checkpoint: Path | None = None
    connect_timeout: float = 5.0

    def __post_init__(self) -> None:
        try:
            integer("workers", self.workers, 1)
        except ConfigError:
            raise EngineError("workers", f"must be an integer >= 1, got {self.workers!r}") from None
        if self.scheduler is not None and not self.scheduler.strip():
            raise EngineError("scheduler", "is empty; give an address like tcp://10.0.0.5:8786 or 'local'")


def tasks_of(n_trials: int, per_task: int) -> list[range]:
    """Trials 0..n−1 in consecutive chunks of ``per_task`` (the last one shorter)."""
    if per_task < 1:
        raise ValueError("per_task must be >= 1")
    return [range(s, min(n_trials, s + per_task)) for s in range(0, n_trials, per_task)]


def trials_per_task(
    seconds_per_trial: float, *, fixed_seconds: float = 0.0, amortise: float = 4.0, at_most: int = 1_000_000
) -> int:
    """Trials per task, from a cost model (never from a clock: the chunking must not depend on the
    machine, or the output would).

    A task is worth ≥ :data:`MIN_TASK_SECONDS` and ≥ ``amortise`` × ``fixed_seconds``, its own fixed
    cost (a Riccati recursion, a Python loop over scans), so that chunking adds at most 1/``amortise``.
    Both scale with ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests set it tiny: one trial per task).
    """
    if not (seconds_per_trial > 0 and math.isfinite(seconds_per_trial)):
        return at_most
    worth = max(MIN_TASK_SECONDS, amortise * fixed_seconds) * (min_task_seconds() / MIN_TASK_SECONDS)
    return int(
        min(at_most, max(1, math.ceil(worth / seconds_per_trial * (1 - 1e-12))))
    )  # no +1 from rounding


def _seconds_from_env(variable: str, default: float, *, zero: bool) -> float:
    """``$variable`` as seconds: a finite number > 0 (≥ 0 with ``zero``), else ``default``."""
    text = os.environ.get(variable)
    try:
        value = float(text) if text else default
    except ValueError:
        return default
    ok = (value >= 0 if zero else value > 0) and math.isfinite(value)
    return value if ok else default


def pool_min_seconds() -> float:
    """:data:`POOL_MIN_SECONDS`, or ``$MOTIONSIG_POOL_MIN_SECONDS`` (tests set 0: every task in the pool, none
    in this process)."""
    return _seconds_from_env("MOTIONSIG_POOL_MIN_SECONDS", POOL_MIN_SECONDS, zero=True)


def min_task_seconds() -> float:
    """:data:`MIN_TASK_SECONDS`, or ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests set it tiny to get many tasks)."""
    return _seconds_from_env("MOTIONSIG_MIN_TASK_SECONDS", MIN_TASK_SECONDS, zero=False)


# ------------------------------------------------------------------------------- run-time limits
@dataclass(frozen=True)
class Budget:
    """How long an interactive run may take (set by the command layer for the command running now).

    Attributes:
        max_minutes: ``--max-minutes``: the limit of the estimated wall time; None: each command's own.
        checkpoint: A checkpoint is kept (``--checkpoint``): no time limit (an interrupted run resumes).
        workers: The workers the run will have, or a function that finds out (asked only when an
            estimate exceeds a limit on one core: a remote scheduler is asked how many workers it has).
    """

    max_minutes: float | None = None
    checkpoint: bool = False
    workers: int | Callable[[], int] = 1

    def n_workers(self) -> int:
        return max(1, int(self.workers() if callable(self.workers) else self.workers))


_BUDGET: contextvars.ContextVar[Budget | None] = contextvars.ContextVar("motionsig_budget", default=None)


@contextlib.contextmanager
def budget(value: Budget) -> Iterator[None]:
    """Run-time checks inside the block (:func:`check_run_time`) use ``value``."""
    token = _BUDGET.set(value)
    try:
        yield
    finally:
        _BUDGET.reset(token)


def available_workers(engine: Engine) -> int:
    """The workers a run on ``engine`` actually has: a local pool ``min(workers, cores)``, a LocalCluster
    its ``workers``, a remote scheduler the workers it reports now."""
    if engine.scheduler is None:
        return max(1, min(engine.workers, default_workers()))
    if engine.scheduler == "local":
        return engine.workers
    with dask_client(engine) as client:
        return max(1, len(client.scheduler_info().get("workers", {})))


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def run_time_limit(limit_s: float) -> float:
    """The interactive limit [s]: ``--max-minutes`` if the command was given it, else ``limit_s``."""
    b = _BUDGET.get() or Budget()
    return limit_s if b.max_minutes is None else 60.0 * b.max_minutes


def check_run_time(
    field: str,
    value: Any,
    seconds: float,
    limit_s: float,
    *,
    what: str = "",
    parallel: bool = True,
    also: str = "",
) -> None:
    """Refuse, before any work, a run whose estimated wall time exceeds the interactive limit.

    The one rule of every command: ``seconds`` (the estimate on one core) is divided by the workers
    the run has (:class:`Budget`; ``parallel=False``: a computation in this process, one worker);
    the limit is ``--max-minutes`` if given, else ``limit_s`` (the command's own); with a checkpoint
    (a Monte Carlo only) there is no time limit. The :class:`ConfigError` names ``field`` with
    ``value`` and states the estimate, the workers, the limit and the ways out (``also``: the
    command's own, before them).
    """
    b = _BUDGET.get() or Budget()
    limit = run_time_limit(limit_s)
    if seconds <= limit or (parallel and b.checkpoint):
        return
    n = b.n_workers() if parallel else 1
    wall = seconds / n
    if wall <= limit:
        return
    on = f"{_duration(seconds)} on one core" + (f", {_duration(wall)} on {n} workers" if n > 1 else "")
    ways = (
        "raise the limit (--max-minutes), add workers (--workers, --scheduler) or keep a checkpoint "
        "(--checkpoint DIR: no time limit, and an interrupted run resumes)"
        if parallel
        else "raise the limit (--max-minutes)"
    )
    raise ConfigError(
        field, value, f"{what}would take an estimated {on}; the limit is {_duration(limit)}: {also}{ways}"
    )


# --------------------------------------------------------------------------------------- checkpoint
def _canonical(identity: Mapping[str, Any]) -> dict[str, Any]:
    """The identity as plain JSON values (tuples → lists, numpy scalars → Python)."""
    return json.loads(json.dumps(identity, sort_keys=True, default=_json_default))


def _json_default(obj: Any) -> Any:
    if hasattr(obj, "tolist"):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


class Checkpoint:
    """Finished task results of one run, kept in a directory (see the module docstring).

    The directory is untrusted input. Each task file holds data only (:mod:`motionsig_cli.taskdata`:
    arrays, numbers, dataclasses of this package; nothing in it can run code), at most
    :data:`MAX_TASK_BYTES`; the index :data:`TASK_INDEX` records each file's size and its HMAC-SHA256
    under the account's secret key (:func:`~motionsig_cli.checkpoint_key.checkpoint_key`) of the run's
    manifest and the file's bytes, and a file is used only if it is a regular file of that size and
    HMAC, decodes, and holds the task's own description. Any other file is recomputed and counted (:attr:`rejected`, one warning);
    an entry that is not a regular file (a directory, a FIFO, a link) is refused by name, before any
    work (the manifest, the index and the task files are never followed as symbolic links, and the index
    is appended to only as a regular file). Checkpoints of version 1 (pickled task files) are refused,
    never read.

    What this promises: whoever writes into the directory without the key (a shared or downloaded
    checkpoint, another account) cannot make the run use a file of their choosing — a task file and index
    line forged, edited, or copied from another task or another run (the manifest is in the HMAC) fail
    the check, and the task is recomputed. Nothing in the directory can run code, read other files or
    exhaust memory. Checkpoints are shared between accounts by giving each run the same key
    (:data:`~motionsig_cli.checkpoint_key.KEY_ENV`); a checkpoint written under another key is recomputed.
    """

    def __init__(self, directory: Path, identity: Mapping[str, Any], tasks: Sequence[Any]) -> None:
        from motionsig_cli import __version__

        self.dir = directory
        self.keys = [repr(t) for t in tasks]  # a task's description, stored beside its result
        self.rejected: list[tuple[str, str]] = []  # (file, reason) of task files recomputed
        digest = hashlib.sha256("\n".join(self.keys).encode()).hexdigest()
        want = {
            "version": CHECKPOINT_VERSION,
            "motionsig": __version__,
            "tasks": len(tasks),
            "task_list_sha256": digest,  # the chunk boundaries: another chunking must not mix in
            **_canonical(identity),
        }
        from motionsig_cli.checkpoint_key import checkpoint_key

        try:
            self._key = checkpoint_key()
        except InputError as exc:
            raise EngineError("checkpoint", str(exc)) from None
        # the run's manifest goes into every task file's HMAC: a file of another run never verifies
        self._run = hashlib.sha256(json.dumps(want, sort_keys=True).encode()).digest()
        manifest = directory / MANIFEST
        if directory.exists() and not directory.is_dir():
            raise EngineError("checkpoint", f"{directory} exists and is not a directory")
        if manifest.exists() or manifest.is_symlink():
            have = _read_manifest(manifest)
            if have.get("version") != CHECKPOINT_VERSION and isinstance(have.get("version"), int):
                raise EngineError(
                    "checkpoint",
                    f"{directory} holds a checkpoint of format version {have.get('version')} (pickled task "
                    f"files, which are never read: they could run code); this version writes format "
                    f"{CHECKPOINT_VERSION}: use a new directory",
                )
            if have.get("command") != want.get("command"):
                raise EngineError(
                    "checkpoint",
                    f"{directory} holds a checkpoint of another command ({_short(have.get('command'))}); "
                    "use a new directory",
                )
            if have != want:
                diff = sorted(str(k) for k in set(have) | set(want) if have.get(k) != want.get(k))
                raise EngineError(
                    "checkpoint",
                    f"{directory} holds a checkpoint of other parameters ({_short(', '.join(diff))} "
                    f"{'differs' if len(diff) == 1 else 'differ'}); use a new directory",
                )
        else:
            if directory.is_dir() and any(directory.iterdir()):
                raise EngineError("checkpoint", f"{directory} is not empty and holds no {MANIFEST}")
            try:
                directory.mkdir(parents=True, exist_ok=True)
                _atomic_write(manifest, json.dumps(want, sort_keys=True, indent=1).encode())
            except OSError as exc:
                raise EngineError(
                    "checkpoint", f"{directory}: cannot write ({exc.strerror or exc})"
                ) from None
        self.index = self._read_index(len(tasks))

    def _path(self, i: int) -> Path:
        return self.dir / f"task-{i:07d}{TASK_SUFFIX}"

    def _mac(self, data: bytes) -> str:
        """HMAC-SHA256 under the checkpoint key of this run's manifest digest and a task file's bytes."""
        return hmac.new(self._key, self._run + data, hashlib.sha256).hexdigest()

    def _read_index(self, n: int) -> dict[int, tuple[int, str]]:
        """Task → (bytes, HMAC) of its file, from :data:`TASK_INDEX` (the last line of a task wins); a line
        that is not an entry (a torn write, an edit) is skipped: its task is recomputed."""
        path = self.dir / TASK_INDEX
        if not (path.exists() or path.is_symlink()):
            return {}
        from motionsig_cli.tables import read_regular

        try:
            data = read_regular(
                path,
                limit=INDEX_LINE_BYTES * max(1, 4 * n) + (1 << 20),
                what="checkpoint index",
                follow=False,
            )
        except InputError as exc:
            raise EngineError("checkpoint", str(exc)) from None
        out: dict[int, tuple[int, str]] = {}
        for line in data.split(b"\n"):
            try:
                entry = json.loads(line) if len(line) <= INDEX_LINE_BYTES else None
            except ValueError:
                entry = None
            if not (isinstance(entry, dict) and set(entry) == {"task", "bytes", "hmac"}):
                continue
            i, size, sha = entry["task"], entry["bytes"], entry["hmac"]
            if type(i) is int and 0 <= i < n and type(size) is int and isinstance(sha, str):
                out[i] = (size, sha)
        return out

    def load(self, i: int) -> tuple[bool, Any]:
        """Task i's result, if its file is the one the index records and holds task i's own description;
        else (False, None): the task is recomputed (a file that was there is counted in :attr:`rejected`).

        Raises:
            EngineError: the task's name is taken by something that is not a regular file.
        """
        path = self._path(i)
        try:
            st = os.lstat(path)
        except FileNotFoundError:
            return False, None
        except OSError as exc:
            raise EngineError("checkpoint", f"{path}: cannot read ({exc.strerror or exc})") from None
        if not stat.S_ISREG(st.st_mode):
            raise EngineError(
                "checkpoint", f"{path} is not a regular file (a directory, link or device?): remove it"
            )
        entry = self.index.get(i)
        if entry is None:
            return self._reject(path, f"not in {TASK_INDEX}")
        size, sha = entry
        if st.st_size != size or size > MAX_TASK_BYTES:
            return self._reject(path, f"{st.st_size} bytes, the index says {size}")
        from motionsig_cli.tables import read_regular
        from motionsig_cli.taskdata import TaskDataError, decode

        try:
            data = read_regular(path, limit=MAX_TASK_BYTES, what="task file", follow=False)
        except InputError as exc:
            raise EngineError("checkpoint", str(exc)) from None
        if not hmac.compare_digest(self._mac(data), sha):
            return self._reject(
                path, "its HMAC differs from the index's (edited, or written under another key)"
            )
        try:
            key, result = decode(data)
        except TaskDataError as exc:
            return self._reject(path, str(exc))
        if key != self.keys[i]:
            return self._reject(path, "it holds another task")
        return True, result

    def _reject(self, path: Path, reason: str) -> tuple[bool, Any]:
        self.rejected.append((path.name, reason))
        return False, None

    def save(self, i: int, result: Any) -> None:
        """Write task i's file, then its line of the index (a file without its line is never used).

        Raises:
            EngineError: the directory cannot be written.
        """
        from motionsig_cli.taskdata import encode

        data = encode(self.keys[i], result)
        if len(data) > MAX_TASK_BYTES:
            _LOG.warning(
                "checkpoint %s: task %d's result is %d bytes, more than %d: not kept", self.dir, i, len(data),
                MAX_TASK_BYTES,
            )  # fmt: skip
            return
        path = self._path(i)
        mac = self._mac(data)
        line = json.dumps({"task": i, "bytes": len(data), "hmac": mac})
        try:
            _atomic_write(path, data)
            _append(self.dir / TASK_INDEX, (line + "\n").encode())
        except OSError as exc:
            raise EngineError("checkpoint", f"{path}: cannot write ({exc.strerror or exc})") from None
        self.index[i] = (len(data), mac)

    def report(self) -> None:
        """One warning if task files were recomputed because they did not match the index."""
        if self.rejected:
            name, why = self.rejected[0]
            _LOG.warning(
                "checkpoint %s: %d task file(s) did not match its index and are recomputed (first: %s: %s)",
                self.dir, len(self.rejected), name, why,
            )  # fmt: skip


def _append(path: Path, data: bytes) -> None:
    """Append ``data`` to the regular file ``path`` (created if absent); a symbolic link or a special file
    there is refused, so that a crafted checkpoint cannot make the run write elsewhere or block."""
    flags = os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_NONBLOCK | getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, flags, 0o644)
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(f"{path.name} is not a regular file")
        os.write(fd, data)
    finally:
        os.close(fd)


def _read_manifest(path: Path) -> dict[str, Any]:
    """The manifest as a JSON object (a regular file of at most :data:`MAX_MANIFEST_BYTES`)."""
    from motionsig_cli.tables import read_regular

    try:
        text = read_regular(path, limit=MAX_MANIFEST_BYTES, what="manifest", follow=False).decode("utf-8")
        have = json.loads(text)
    except InputError as exc:
        raise EngineError("checkpoint", str(exc)) from None
    except (ValueError, RecursionError) as exc:
        raise EngineError("checkpoint", f"{path}: unreadable manifest ({_short(str(exc))})") from None
    if not isinstance(have, dict):
        raise EngineError("checkpoint", f"{path}: unreadable manifest (not a JSON object)")
    return have


def _short(value: Any, limit: int = 200) -> str:
    """``value`` as text of at most ``limit`` characters (a crafted manifest's text is not echoed in full)."""
    text = value if isinstance(value, str) else repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _atomic_write(path: Path, data: bytes) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


# ------------------------------------------------------------------------------------------ running
def run_tasks(
    fn: Callable[[Any], R],
    tasks: Sequence[Any],
    engine: Engine,
    *,
    sizes: Sequence[int] | None = None,
    progress: Callable[[int], None] | None = None,
    identity: Mapping[str, Any] | None = None,
    consume: Callable[[int, Any], None] | None = None,
) -> list[R]:
    """``[fn(t) for t in tasks]``, computed where ``engine`` says, returned in task order.

    Args:
        fn: A picklable, deterministic function (module-level, or a ``functools.partial`` of one).
        tasks: Picklable task descriptions (e.g. ``range`` objects of trial ids).
        engine: Workers, scheduler and checkpoint.
        sizes: Trials per task, for ``progress`` (default 1 per task).
        progress: Called with a task's size each time a task finishes (in completion order).
        identity: The command and its parameters (JSON values); required with a checkpoint.
        consume: Called with ``(i, result)`` in task order, as soon as tasks 0..i have finished; the result
            is then dropped (the list returned holds None), so that a long run holds only the results that
            finished ahead of an earlier task (with a pool, at most two per worker in flight), and a
            checkpoint's results are read back one at a time as they are consumed.
    """
    n = len(tasks)
    sizes = list(sizes) if sizes is not None else [1] * n
    results: list[Any] = [None] * n
    done = [False] * n
    stored = [False] * n  # done in the checkpoint, read back when consumed
    ckpt: Checkpoint | None = None
    if engine.checkpoint is not None:
        if identity is None:
            raise ValueError("a checkpoint needs the run's identity")
        ckpt = Checkpoint(engine.checkpoint, identity, tasks)
        for i in range(n):
            done[i], results[i] = ckpt.load(i)
            if done[i] and consume is not None:
                results[i], stored[i] = None, True
            if done[i] and progress is not None:
                progress(sizes[i])
        ckpt.report()
    pending = [i for i in range(n) if not done[i]]
    next_out = 0

    def flush() -> None:
        nonlocal next_out
        while consume is not None and next_out < n and done[next_out]:
            i = next_out
            if stored[i]:
                assert ckpt is not None
                ok, value = ckpt.load(i)
                if not ok:  # pragma: no cover - the file was read a moment ago
                    raise EngineError("checkpoint", f"task {i}'s file changed while the run resumed")
            else:
                value = results[i]
            results[i] = None
            next_out += 1
            consume(i, value)

    def finish(i: int, value: Any) -> None:
        results[i] = value
        done[i] = True
        if ckpt is not None:
            ckpt.save(i, value)
        if progress is not None:
            progress(sizes[i])
        flush()

    flush()

    with one_blas_thread():
        if engine.scheduler is not None:
            if pending:  # a fully restored checkpoint needs no cluster
                _run_dask(fn, tasks, pending, engine, finish)
        elif engine.workers == 1 or len(pending) <= 1:
            for i in pending:
                finish(i, fn(tasks[i]))
        else:
            _run_pool(fn, tasks, pending, min(engine.workers, len(pending)), finish)
    flush()
    return results


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """This process's BLAS and OpenMP libraries with one thread each inside the block (as every worker has:
    :data:`BLAS_THREADS`).

    The tasks are small matrices and element-wise steps, where a BLAS thread pool gains nothing, and its
    threads, spinning after each call, take the core that another worker computes on: on an idle 2-core
    machine the 187-filter bank ran 2-10 % faster alone with one thread, and two processes side by side
    each lost 1-2 % with one thread, 4-6 % with the default thread count.
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"), threadpool_limits(limits=1, user_api="openmp"):
        yield


@runtime_checkable
class MonteCarloJob(Protocol[R]):
    """A Monte Carlo run, as the engine sees it: the one protocol every command's experiment implements.

    A job is a frozen, picklable dataclass of everything its results depend on. ``name`` (a class
    attribute) and :meth:`identity` go into a checkpoint's manifest; :meth:`tasks` lists the chunks of
    trials from the job's cost model (never from the worker count or a clock); :meth:`run_task` computes
    one chunk (it runs in a worker, so it may touch nothing but the job and the task);
    :meth:`reduce` joins the chunks' results, in task order, into the job's result. :func:`run_job`
    runs any job.

    Examples:
        >>> from dataclasses import dataclass
        >>> from motionsig_cli import MonteCarloJob, run_job, trial_rng
        >>> @dataclass(frozen=True)
        ... class Coins:  # a MonteCarloJob: 10 coin flips in tasks of 4, counting heads
        ...     name = "coins"
        ...     trials: int = 10
        ...     seed: int = 0
        ...     def identity(self): return {"trials": self.trials, "seed": self.seed}
        ...     def tasks(self): return [range(i, min(i + 4, self.trials)) for i in range(0, self.trials, 4)]
        ...     def task_size(self, task): return len(task)
        ...     def run_task(self, task): return sum(int(trial_rng(self.seed, t).integers(2)) for t in task)
        ...     def reduce(self, tasks, results): return sum(results)
        >>> job: MonteCarloJob[int] = Coins()
        >>> run_job(job) == sum(int(trial_rng(0, t).integers(2)) for t in range(10))  # however it is chunked
        True
    """

    name: str

    def tasks(self) -> Sequence[Any]:
        """The chunks of trials, in the order their results are reduced."""
        ...

    def task_size(self, task: Any) -> int:
        """Trials in ``task`` (progress counts trials)."""
        ...

    def run_task(self, task: Any) -> Any:
        """One chunk's result (deterministic: trial t draws only from its own seed child)."""
        ...

    def reduce(self, tasks: Sequence[Any], results: Sequence[Any]) -> R:
        """The job's result from every task's result, given in task order."""
        ...

    def identity(self) -> dict[str, Any]:
        """Everything the results depend on (JSON values), for a checkpoint's manifest."""
        ...


def run_job(
    job: MonteCarloJob[R], engine: Engine | None = None, *, progress: Callable[[int], None] | None = None
) -> R:
    """Run ``job`` on ``engine`` (default: in this process): :meth:`~MonteCarloJob.run_task` over its
    tasks with :func:`run_tasks`, then :meth:`~MonteCarloJob.reduce`. ``progress`` is called with the
    number of trials of each finished task.

    Examples:
        Govaers' SLRT study of three runs (a job of the ``existence`` system), in this process; the result
        does not depend on the engine, since trial t draws from its own seed child:

        >>> from motionsig_cli import Engine, run_job
        >>> from motionsig_cli.existence.slrt import SlrtScenario, SlrtStudy
        >>> job = SlrtStudy(SlrtScenario(), pd=(0.9,), no_target=False, runs=3).job()
        >>> done = []
        >>> first = run_job(job, Engine(workers=1), progress=done.append)
        >>> sum(done)  # trials, counted as their tasks finish
        3
        >>> again = run_job(job)
        >>> all((a[k] == b[k]).all() for a, b in zip(first, again) for k in a)  # log LR per method
        True
    """
    tasks = list(job.tasks())
    results = run_tasks(
        job.run_task,
        tasks,
        Engine() if engine is None else engine,
        sizes=[job.task_size(t) for t in tasks],
        progress=progress,
        identity={"command": job.name, **job.identity()},
    )
    return job.reduce(tasks, results)


def job_trials(job: MonteCarloJob[Any]) -> int:
    """The job's total number of trials (for a progress bar)."""
    return int(sum(job.task_size(t) for t in job.tasks()))


PARENT_POLL_S = 0.5
"""How often a pool worker checks that the process that started it is still alive [s]."""


def _ignore_sigint(parent: int | None = None) -> None:
    """Worker initializer: Ctrl-C is the main process's business; and the worker dies with its parent.

    Whatever ends the parent (SIGKILL, the OOM killer, a closed terminal) gives it no chance to stop its
    pool, so each worker watches for itself: a daemon thread polls ``os.getppid()`` every
    :data:`PARENT_POLL_S` s and, once the worker has been re-parented, exits at once (``os._exit``: a
    dead parent has nobody to report to). The resource tracker exits on its own when the last process
    holding its pipe is gone.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if parent is None:
        return
    import threading

    def watch() -> None:
        while True:
            if os.getppid() != parent:
                os._exit(1)
            time.sleep(PARENT_POLL_S)

    threading.Thread(target=watch, name="motionsig-parent-watch", daemon=True).start()


@contextlib.contextmanager
def _children_ignore_sigint() -> Iterator[None]:
    """Block SIGINT in this thread while child processes (and threads that spawn them) are created.

    A blocked signal mask is inherited across fork and exec, so the children never see the terminal's
    Ctrl-C, not even during their start-up (imports take ~1 s; a worker initializer would come too late).
    This thread gets the signal when the block ends: a Ctrl-C in the meantime is deferred, not lost.
    """
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        yield
        return
    # multiprocessing's resource tracker, started with the first child, *unblocks* SIGINT in the thread
    # that starts it (CPython resource_tracker.py): start it now, before the block
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


BLAS_THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""Thread counts a pool worker starts with (1 each, unless set by the user): N workers on N cores, each with
a BLAS thread pool of N, would fight for the cores (Dask's nanny does the same for its workers)."""

_WORKER_FN: list[Callable[[Any], Any]] = []


def _worker_init(parent: int | None, fn: Callable[[Any], Any]) -> None:
    """Pool worker initializer: :func:`_ignore_sigint`, and keep the task function (the job, with its arrays),
    which is pickled once per worker here instead of once per task."""
    _ignore_sigint(parent)
    _WORKER_FN[:] = [fn]


PROBE = -1
"""The index under which a worker's probe (:func:`_ready`) is in flight."""

QUEUED_PER_WORKER = 1
"""Tasks sent to a pool worker beyond the one it runs while at least 2 × workers tasks are left."""


def _ready() -> bool:
    """A pool worker's first call: it returns once the worker has started (imports and job included), so
    that no task is sent to a worker that is still starting, where it could hold up the end of a run."""
    return True


def _call(task: Any) -> Any:
    """A task in a pool worker: the function :func:`_worker_init` kept, on ``task``."""
    return _WORKER_FN[0](task)


@contextlib.contextmanager
def _blas_single_thread() -> Iterator[None]:
    """:data:`BLAS_THREADS` = 1 in the environment the workers spawned inside the block inherit (this
    process's own BLAS read its settings when it was loaded: it is not affected)."""
    old = {k: os.environ.get(k) for k in BLAS_THREADS}
    os.environ.update({k: "1" for k, v in old.items() if v is None})
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)


class _Shared:
    """The pending task indices, taken one at a time by this process and by the pool's feeder thread."""

    def __init__(self, pending: Sequence[int]) -> None:
        self.queue = list(reversed(pending))
        self.lock = threading.Lock()

    def take(self) -> int | None:
        with self.lock:
            return self.queue.pop() if self.queue else None

    def left(self) -> int:
        with self.lock:
            return len(self.queue)


def _run_pool(
    fn: Callable[[Any], Any],
    tasks: Sequence[Any],
    pending: list[int],
    workers: int,
    finish: Callable[[int, Any], None],
) -> None:
    """The pending tasks on ``workers`` processes: this one and ``workers − 1`` spawned ones (all of them
    spawned when :func:`pool_min_seconds` is 0, the tests' setting).

    This process computes tasks from the start; a feeder thread waits :func:`pool_min_seconds`, then
    (if tasks are left) spawns the pool, sends each worker a probe (:func:`_ready`) and, once a worker has
    answered it, keeps two tasks in flight per worker (one, near the end: :data:`QUEUED_PER_WORKER`),
    taking the next pending task each time one finishes.
    So a run shorter than that never pays for a pool, the pool's start-up (≈ 0.35 s of a core per worker
    on an idle machine) overlaps with work here, a run that ends while its workers start waits for none of
    them (they are stopped), and near the end no task waits in a queue behind a busy worker while another
    is idle.
    Results from the pool are handed to ``finish`` here, between this process's own tasks. Which process
    runs a task never changes what it computes.
    """
    delay = pool_min_seconds()
    here = delay > 0  # this process computes too
    n_pool = workers - 1 if here else workers
    shared = _Shared(pending)
    done: queue.SimpleQueue[tuple[int, Future[Any]] | None] = queue.SimpleQueue()
    stop = threading.Event()
    holder: list[ProcessPoolExecutor] = []
    made = threading.Lock()
    used = threading.Event()  # a task was sent to the pool (else it can be stopped without waiting)
    errors: list[BaseException] = []

    def feed() -> None:
        inflight: dict[Future[Any], int] = {}
        try:
            if stop.wait(delay) or shared.left() == 0:
                return
            with made:
                if stop.is_set():
                    return
                # spawn, not fork: the parent holds threads (progress bar, this one) whose locks a fork copies
                pool = ProcessPoolExecutor(
                    max_workers=n_pool,
                    mp_context=multiprocessing.get_context("spawn"),
                    initializer=_worker_init,
                    initargs=(os.getpid(), fn),
                )
                holder.append(pool)
                with _children_ignore_sigint(), _blas_single_thread():  # processes spawn on these submits
                    for _ in range(n_pool):  # a probe per worker: it returns once the worker is up
                        inflight[pool.submit(_ready)] = PROBE
            ready = 0  # workers whose probe has returned
            while inflight:
                if shared.left() == 0 and all(i == PROBE for i in inflight.values()):
                    return  # every task was taken here while the workers started: the pool has no work
                finished, _ = wait(inflight, timeout=0.05, return_when=FIRST_COMPLETED)
                failed = False
                for fut in sorted(finished, key=inflight.__getitem__):
                    i = inflight.pop(fut)
                    done.put((i, fut))
                    failed |= fut.exception() is not None
                    ready += i == PROBE and not failed
                # a task per ready worker, and one queued behind it while many are left (it then starts
                # as soon as the one before ends, not once this thread gets the interpreter back: the
                # round trip idled the worker 3 % of its time, measured), so that no worker waits
                depth = 1 + QUEUED_PER_WORKER * (shared.left() >= 2 * workers)
                while (
                    not (failed or stop.is_set())
                    and sum(v != PROBE for v in inflight.values()) < ready * depth
                ):
                    if (i := shared.take()) is None:
                        break
                    inflight[pool.submit(_call, tasks[i])] = i
                    used.set()
                if stop.is_set() and not finished:
                    return
        except BaseException as exc:  # reported in the main thread
            errors.append(exc)
        finally:
            done.put(None)

    feeder = threading.Thread(target=feed, name="motionsig-pool-feeder", daemon=True)
    ok = False
    fed = False

    def collect(block: bool) -> bool:
        """Hand finished pool results to ``finish``; True once the feeder has ended."""
        nonlocal fed
        while not fed:
            try:
                item = done.get(block=block)
            except queue.Empty:
                return fed
            if item is None:
                fed = True
                if errors:
                    _raise_pool_error(errors[0])
                return True
            i, fut = item
            try:
                value = fut.result()
            except BrokenProcessPool as exc:
                _raise_pool_error(exc)
            if i != PROBE:
                finish(i, value)
        return True

    try:
        with _children_ignore_sigint():  # the feeder thread and the pool it spawns start with SIGINT blocked
            feeder.start()
        while here and (i := shared.take()) is not None:
            finish(i, fn(tasks[i]))
            collect(block=False)
        while not collect(block=True):
            pass
        if shared.left():  # the feeder ended early (a worker failed): the rest runs here
            while (i := shared.take()) is not None:
                finish(i, fn(tasks[i]))
        ok = True
    finally:
        stop.set()
        with made:
            pool = holder[0] if holder else None
        if pool is not None:
            if ok and used.is_set():
                pool.shutdown(wait=True)
            else:  # interrupted or failed, or no task ever sent: do not wait for the workers
                _kill_pool(pool)
        feeder.join(timeout=10)


def _raise_pool_error(exc: BaseException) -> NoReturn:
    """Raise ``exc``, a lost worker (a broken pool: a future's error, or a submit to the broken pool) as
    :class:`WorkerDied`."""
    if isinstance(exc, BrokenProcessPool):
        raise WorkerDied("a worker process died (killed, or out of memory?) while it ran a task") from exc
    raise exc


def _kill_pool(pool: ProcessPoolExecutor) -> None:
    """Stop a pool at once: cancel its queued tasks and terminate its processes."""
    procs = list(getattr(pool, "_processes", {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        with contextlib.suppress(Exception):
            p.terminate()
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(timeout=5)
    with contextlib.suppress(Exception):  # let the manager thread see the dead pool and exit now
        pool.shutdown(wait=True, cancel_futures=True)


def split_address(address: str) -> tuple[str, int]:
    """(host, port) of ``tcp://host:port`` or ``host:port``."""
    rest = address.strip()
    if "://" in rest:
        proto, rest = rest.split("://", 1)
        if proto != "tcp":
            raise EngineError(
                "scheduler",
                f"{address!r}: only tcp:// addresses (or 'local'); TLS clusters are not supported",
            )
    host, sep, port = rest.rpartition(":")
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise EngineError("scheduler", f"{address!r} is not an address like tcp://10.0.0.5:8786 (or 'local')")
    return host.strip("[]"), int(port)


@contextlib.contextmanager
def dask_client(engine: Engine, n_workers: int | None = None) -> Iterator[Any]:
    """A ``distributed.Client`` for ``engine.scheduler`` (a LocalCluster of ``n_workers``, default
    ``engine.workers``, for ``"local"``)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise EngineError("scheduler", f"needs Dask, which is not installed: {DASK_EXTRA}") from None
    if engine.scheduler == "local":
        import dask

        cluster = None
        try:
            # the cluster's event-loop thread and worker processes start with SIGINT blocked (see
            # _children_ignore_sigint); a Ctrl-C during start-up is raised here once it is up
            with dask.config.set({TRIM_KEY: None}), _children_ignore_sigint():  # see TRIM_KEY
                cluster = LocalCluster(
                    n_workers=engine.workers if n_workers is None else n_workers,
                    threads_per_worker=1,
                    processes=True,
                    host="127.0.0.1",
                    dashboard_address=":0",  # a free port: 8787 may be taken
                    silence_logs=logging.CRITICAL + 1,  # task errors reach the user as one line, not as logs
                )
            with Client(cluster) as client:
                yield client
        finally:
            if cluster is not None:
                cluster.close()
        return
    assert engine.scheduler is not None
    host, port = split_address(engine.scheduler)
    _probe_scheduler(engine.scheduler, host, port, engine.connect_timeout)
    try:
        client = Client(engine.scheduler, timeout=engine.connect_timeout)
    except Exception as exc:  # whatever answered there is not a Dask scheduler we can use
        raise EngineError(
            "scheduler", f"no Dask scheduler answers at {engine.scheduler} ({type(exc).__name__}: {exc})"
        ) from None
    try:
        yield client
    finally:
        client.close()


def _probe_scheduler(address: str, host: str, port: int, timeout: float) -> None:
    """Fail fast: a TCP connect, then the scheduler's handshake, which it sends unasked at once. A closed
    port, a silent server or one that waits for a request (HTTP) fails here within ``timeout``; the Dask
    client itself would wait for much longer."""
    try:
        with socket.create_connection((host, port), timeout=timeout) as sock:
            sock.settimeout(timeout)
            if not sock.recv(1):
                raise OSError("the connection was closed")
    except TimeoutError:
        raise EngineError(
            "scheduler",
            f"{address} accepts connections but sends no Dask handshake (not a Dask scheduler?)",
        ) from None
    except OSError as exc:
        raise EngineError(
            "scheduler", f"cannot reach the Dask scheduler at {address} ({exc.strerror or exc})"
        ) from None


def _apply(fn: Callable[[Any], Any], task: Any) -> Any:
    """A task on a Dask worker: ``fn`` is the result of :func:`_same` (fetched once per worker, then kept),
    the task comes with each call."""
    return fn(task)


def _same(value: Any) -> Any:
    """The job as a Dask task's result: unlike scattered data, which is gone once the workers holding it
    die, a task's result is recomputed wherever it is lost, so a worker's death costs a retry, not the run."""
    return value


@dataclass(frozen=True, slots=True)
class _Outcome:
    """A task's result or the exception it raised."""

    result: Any = None
    error: BaseException | None = None

    @classmethod
    def of(cls, get: Callable[[], Any]) -> _Outcome:
        try:
            return cls(get())
        except Exception as exc:
            return cls(error=exc)

    def value(self) -> Any:
        if self.error is not None:
            from distributed import KilledWorker

            if isinstance(self.error, KilledWorker):  # the task's workers died, as many as Dask allows
                raise WorkerDied(
                    "Dask workers died while they ran a task (killed, or out of memory?)"
                ) from self.error
            raise self.error
        return self.result


def _run_dask(
    fn: Callable[[Any], Any],
    tasks: Sequence[Any],
    pending: list[int],
    engine: Engine,
    finish: Callable[[int, Any], None],
) -> None:
    """The pending tasks on the Dask cluster of ``engine``. A feeder thread connects (or starts the
    LocalCluster), sends ``fn`` to the workers (:func:`_same`) and submits the tasks; results are handed to
    ``finish`` here.

    A LocalCluster of N workers is, as a local pool, this process and N − 1 Dask workers: this process
    computes tasks from the start, beside the cluster while it starts (≈ 1 s of a core per worker for its
    imports) and after, taking tasks from the same queue; each cluster worker has one task in flight, so that
    no task waits behind a busy worker at the end of the run. (``workers=1``: one Dask worker; this process
    computes only while it starts.) A remote cluster's client only waits, with two tasks in flight per
    worker (bounded memory, early checkpoints, a prompt Ctrl-C)."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise EngineError("scheduler", f"needs Dask, which is not installed: {DASK_EXTRA}") from None
    local = engine.scheduler == "local"
    here = local and engine.workers > 1  # this process is one of the workers
    shared = _Shared(pending)
    done: queue.SimpleQueue[tuple[int, _Outcome] | None] = queue.SimpleQueue()
    ready = threading.Event()
    stop = threading.Event()
    errors: list[BaseException] = []

    def feed() -> None:
        try:
            with dask_client(engine, engine.workers - 1 if here else None) as client:
                from distributed import wait as dask_wait

                ready.set()
                if stop.is_set():
                    return
                fn_f = client.submit(_same, fn, pure=False)  # not scatter: see _same
                n_workers = max(1, len(client.scheduler_info().get("workers", {})))
                futures: dict[Any, int] = {}
                left: set[Any] = set()

                def in_flight() -> int:
                    """Two tasks a worker, so that it never waits for the client's round trip (≈ 11 ms a task
                    on a LocalCluster); one at the end of a local run, where a second task could wait behind
                    a busy worker while this process is idle."""
                    return n_workers * (2 if not local or shared.left() > 2 * (n_workers + here) else 1)

                def top_up() -> None:
                    while len(left) < in_flight() and not stop.is_set() and (i := shared.take()) is not None:
                        fut = client.submit(_apply, fn_f, tasks[i], pure=False)
                        futures[fut] = i
                        left.add(fut)

                top_up()
                while left:
                    if stop.is_set():  # interrupted, or a task failed
                        with contextlib.suppress(Exception):
                            client.cancel(list(left))
                        return
                    try:
                        finished, _ = dask_wait(list(left), timeout=0.2, return_when="FIRST_COMPLETED")
                    except TimeoutError:  # nothing finished yet
                        continue
                    for fut in finished:  # fetched here: the futures end with the client
                        left.discard(fut)
                        done.put((futures.pop(fut), _Outcome.of(fut.result)))
                    top_up()
        except BaseException as exc:  # reported in the main thread
            errors.append(exc)
        finally:
            ready.set()
            done.put(None)

    def collect(block: bool) -> bool:
        """Hand finished cluster results to ``finish``; True once the feeder has ended."""
        while True:
            try:
                item = done.get(block=block)
            except queue.Empty:
                return False
            if item is None:
                if errors:
                    raise errors[0]
                return True
            i, outcome = item
            finish(i, outcome.value())

    feeder = threading.Thread(target=feed, name="motionsig-dask-feeder", daemon=True)
    try:
        with _children_ignore_sigint():  # the cluster's threads and processes start with SIGINT blocked
            feeder.start()
        fed = False
        while (here or (local and not ready.is_set())) and (i := shared.take()) is not None:
            finish(i, fn(tasks[i]))
            if collect(block=False):
                fed = True
                break
        if not fed:
            collect(block=True)
        if shared.left():  # the cluster ended early with tasks left (no failure): they run here
            while (i := shared.take()) is not None:
                finish(i, fn(tasks[i]))
    finally:
        stop.set()
        feeder.join(timeout=30)
