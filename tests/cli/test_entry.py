"""The console-script entry point."""

import builtins

from motionsig_cli.cli import entry


def test_ctrl_c_during_the_imports_is_one_line_and_exit_130(monkeypatch, capsys):
    real = builtins.__import__

    def interrupted(name, *args, **kwargs):
        if name == "motionsig_cli.cli.app":
            raise KeyboardInterrupt
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", interrupted)
    assert entry.main() == 130
    assert capsys.readouterr().err == "motionsig: interrupted\n"


def test_the_entry_point_runs_the_app(monkeypatch, capsys):
    monkeypatch.setattr("sys.argv", ["motionsig", "--version"])
    assert entry.main() == 0
    assert capsys.readouterr().out.startswith("motionsig ")
