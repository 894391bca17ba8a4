"""Helpers shared by the CLI tests: run the app in-process, read a CSV result back."""

from pathlib import Path

import pytest

from motionsig_cli.cli.app import main
from motionsig_cli.tables import Table, read_table

# a small `detect --montecarlo` run (the engine tests and the bad-input table use it)
MC_1D = ("detect", "--montecarlo", "--trials", "6", "--fr-list", "0.01,0.1", "--R-list", "1e-2,1e-3",
         "--horizons", "5,10")  # fmt: skip


def run(capsys, *args: str) -> tuple[int, str, str]:
    """Run ``motionsig *args`` in-process; return (exit code, stdout, stderr)."""
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


def table(text: str, tmp_path, name: str = "t.csv") -> Table:
    """Parse a command's CSV output (provenance lines included) through a file."""
    p = tmp_path / name
    p.write_text(text)
    return read_table(p)


def engine_outputs(capsys, tmp_path, dask_address: str, *args: str) -> dict[str, bytes]:
    """Run ``motionsig *args -o FILE`` with 1 worker, 2 workers and on the Dask cluster at
    ``dask_address``; return each run's output bytes (they must be identical)."""
    outs = {}
    for name, engine in (
        ("w1", ("--workers", "1")),
        ("w2", ("--workers", "2")),
        ("dask", ("--scheduler", dask_address)),
    ):
        path = tmp_path / f"engine_{name}.csv"
        rc, _, err = run(capsys, *args, *engine, "-o", str(path), "-q")
        assert rc == 0, err
        outs[name] = path.read_bytes()
    return outs


def one_line_error(capsys, *args: str) -> str:
    """Run ``motionsig *args``; assert it fails with exit code 2, nothing on stdout and a one-line message
    without a traceback; return the message."""
    rc, out, err = run(capsys, *args)
    assert rc == 2 and out == "", err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def task_count(tmp_path, capsys, *args: str) -> int:
    """Number of tasks a run is split into (the task files of a fresh checkpoint)."""
    ckpt = tmp_path / "count"
    rc, _, err = run(
        capsys, *args, "--workers", "1", "--checkpoint", str(ckpt), "-o", str(tmp_path / "n.csv"), "-q"
    )
    assert rc == 0, err
    return len(list(ckpt.glob("task-*.task")))


def checkpoint_resume(capsys, tmp_path, args: tuple[str, ...], drop: slice) -> tuple[Path, int]:
    """Run ``motionsig *args`` uninterrupted and with ``--checkpoint DIR`` (1 worker), delete the task files
    ``drop`` selects (an interrupted run) and resume with 2 workers: the three outputs must be
    byte-identical and the resumed run must write every task file again. Return (DIR, number of tasks)."""
    ckpt = tmp_path / "ckpt"
    whole, first, resumed = (tmp_path / f"{n}.csv" for n in ("whole", "first", "resumed"))
    rc, _, err = run(capsys, *args, "--workers", "1", "-o", str(whole), "-q")
    assert rc == 0, err
    rc, _, err = run(capsys, *args, "--workers", "1", "--checkpoint", str(ckpt), "-o", str(first), "-q")
    assert rc == 0, err
    files = sorted(ckpt.glob("task-*.task"))
    for f in files[drop]:
        f.unlink()
    rc, _, err = run(capsys, *args, "--workers", "2", "--checkpoint", str(ckpt), "-o", str(resumed), "-q")
    assert rc == 0, err
    assert resumed.read_bytes() == first.read_bytes() == whole.read_bytes()
    assert len(list(ckpt.glob("task-*.task"))) == len(files)
    return ckpt, len(files)


def bad_engine_options_test(*base: str):
    """A test that ``motionsig *base`` with ``--workers 0`` or a blank ``--scheduler`` fails with a one-line
    error naming the option and writes no file (assign it to a ``test_*`` name of a test module)."""

    @pytest.mark.parametrize(
        ("args", "needle"), [(("--workers", "0"), "--workers"), (("--scheduler", " "), "--scheduler")]
    )
    def test(capsys, tmp_path, args, needle):
        out = tmp_path / "o.csv"
        assert needle in one_line_error(capsys, *base, *args, "-o", str(out)) and not out.exists()

    return test
