"""Helpers shared by the CLI tests: run the app in-process, read a CSV result back."""

from motionsig_cli.cli.app import main
from motionsig_cli.tables import Table, read_table


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
