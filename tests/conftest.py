"""Shared fixtures: one Dask LocalCluster for the whole session (engine tests pass its address)."""

import logging
import os
import tempfile

import pytest

# The checkpoint key (motionsig_cli.checkpoint_key) of the test session: a key file made in a directory of
# its own, never the user's configuration directory; subprocesses inherit it.
os.environ.pop("MOTIONSIG_CHECKPOINT_KEY", None)
os.environ["XDG_CONFIG_HOME"] = tempfile.mkdtemp(prefix="motionsig-tests-config-")


@pytest.fixture(scope="session")
def dask_address():
    """Address of a 2-worker Dask LocalCluster on 127.0.0.1 (skips when the dask extra is missing)."""
    distributed = pytest.importorskip("distributed")
    import dask

    from motionsig_cli.engine import TRIM_KEY

    with dask.config.set({TRIM_KEY: None}):  # as the engine's own LocalCluster (see engine.TRIM_KEY)
        cluster = distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=":0",  # a free port: 8787 may be taken
            silence_logs=logging.CRITICAL,  # task errors reach the user as one line, not as worker logs
        )
    try:
        yield cluster.scheduler_address
    finally:
        cluster.close()


@pytest.fixture
def many_tasks(monkeypatch):
    """Chunk Monte Carlo runs into tiny tasks and always start the pool, so that 2 workers really share the work."""
    monkeypatch.setenv("MOTIONSIG_MIN_TASK_SECONDS", "1e-9")
    monkeypatch.setenv("MOTIONSIG_POOL_MIN_SECONDS", "0")  # and use the pool even for a tiny run
