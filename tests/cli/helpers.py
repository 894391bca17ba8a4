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
