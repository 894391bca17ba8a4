"""The application layer: lazy command loading, summaries, completion, one error prefix, progress, the
option groups and the mapping of the core's ConfigError to option names."""

import subprocess
import sys
from pathlib import Path

import pytest
import typer

from motionsig_cli.cli import app as app_mod
from motionsig_cli.cli import common
from motionsig_cli.cli.app import COMMANDS, load_command, main, summary_of
from motionsig_cli.config import ConfigError

from .helpers import run

LIGHT = ("numpy", "scipy", "matplotlib", "rich", "motionsig_cli.engine")


def _imported_after(*argv: str) -> set[str]:
    """The modules a fresh interpreter has imported after running ``motionsig argv``."""
    code = (
        "import sys\n"
        "from motionsig_cli.cli.app import main\n"
        f"rc = main({list(argv)!r})\n"
        "print(' '.join(sorted(sys.modules)))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(out.stdout.splitlines()[-1].split())


def test_help_imports_no_command_and_no_numerical_package():
    mods = _imported_after("--help")
    assert not [m for m in mods if m.split(".")[0] in LIGHT or m in LIGHT]
    commands = {module for module, _, _ in COMMANDS.values()}
    assert not commands & mods


def test_a_command_imports_only_its_own_module():
    mods = _imported_after("encode", "gps", "--prn", "1")
    others = {module for name, (module, _, _) in COMMANDS.items() if name != "encode"}
    assert "motionsig_cli.cli.encode" in mods
    assert not others & mods
    assert not [m for m in mods if (m.split(".")[0] in LIGHT or m in LIGHT) and m.split(".")[0] != "numpy"]


@pytest.mark.parametrize("name", list(COMMANDS))
def test_the_root_summary_is_the_commands_own_first_paragraph(name):
    cmd = load_command(name)
    assert COMMANDS[name][2] == summary_of(cmd.help)


@pytest.mark.parametrize("name", list(COMMANDS))
def test_subcommand_summaries_are_never_cut(name):
    cmd = load_command(name)
    for sub in getattr(cmd, "commands", {}).values():
        assert sub.get_short_help_str(limit=45) == summary_of(sub.help)


def test_summary_keeps_a_period_inside_the_first_paragraph():
    assert summary_of("Fig. 3.2: densities.\n  More on the line.\n\nSecond paragraph.") == (
        "Fig. 3.2: densities. More on the line."
    )


def test_root_help_lists_every_command_and_completion(capsys):
    rc, out, _ = run(capsys, "--help")
    assert rc == 0
    for name in COMMANDS:
        assert f"  {name} " in out
    assert "--install-completion" in out and "--show-completion" in out


def test_shell_completion_script_names_the_program():
    env = {"_MOTIONSIG_COMPLETE": "complete_bash", "COMP_WORDS": "motionsig tra", "COMP_CWORD": "1"}
    code = "from motionsig_cli.cli.app import main; raise SystemExit(main())"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env={**env, "PATH": "/usr/bin:/bin"}
    )
    assert "track-sat" in out.stdout


def test_an_unknown_command_is_one_line_with_the_program_prefix(capsys):
    rc, _, err = run(capsys, "nonsense")
    assert rc == 2
    assert err.startswith("motionsig: error: ") and err.count("\n") == 1


@pytest.mark.parametrize(
    "argv, prefix",
    [
        (("detect", "--example", "3d"), "motionsig detect: error: "),
        (("encode", "gps", "--prn", "x"), "motionsig encode gps: error: "),
        (("jam-bound", "table", "--which", "9.9"), "motionsig jam-bound table: error: "),
    ],
)
def test_option_errors_name_the_command_and_no_validator(capsys, argv, prefix):
    rc, _, err = run(capsys, *argv)
    assert rc == 2, err
    assert err.startswith(prefix), err
    assert "Value error" not in err and "Input should" not in err
    assert err.count("\n") == 1


def test_input_errors_carry_the_command_prefix(capsys, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\n")
    rc, _, err = run(capsys, "detect", str(bad))
    assert rc == 2
    assert err.startswith("motionsig detect: error: "), err


def test_the_default_seed_matches_the_core():
    from motionsig_cli.rng import DEFAULT_SEED

    assert common.DEFAULT_SEED == DEFAULT_SEED


def test_progress_is_shown_when_stderr_is_a_terminal_even_if_stdout_is_a_pipe(monkeypatch):
    monkeypatch.setattr(sys.stdout, "isatty", lambda: False, raising=False)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    with common.progress(quiet=False) as bar:
        assert not bar.disable
    with common.progress(quiet=True) as bar:
        assert bar.disable
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False, raising=False)
    with common.progress(quiet=False) as bar:
        assert bar.disable


# ------------------------------------------------------------------------- the command decorator
def _probe_app() -> typer.Typer:
    """A tiny app whose command raises the core's ConfigError for the field it is told to."""
    probe = typer.Typer(add_completion=False)

    @probe.command()
    @common.command(parallel=True, options={"meas_model": "--meas"})
    def go(
        field: str = typer.Option("sigma_r", "--field"),
        *,
        output: common.Output,
        parallel: common.Parallel,
    ) -> None:
        if field == "none":
            typer.echo(f"{output.fmt.value} {output.out} {output.quiet} {parallel.workers}")
            return
        raise ConfigError(field, 0.0, "is not a finite number > 0")

    return probe


@pytest.mark.parametrize(
    "field, option",
    [("sigma_r", "--sigma-r"), ("meas_model", "--meas"), ("T", "--T"), ("workers", "--workers")],
)
def test_a_config_error_names_the_option_that_set_the_field(field, option):
    from typer._click.exceptions import BadParameter

    cmd = typer.main.get_command(_probe_app())
    with pytest.raises(BadParameter) as exc:
        cmd.main(["--field", field], standalone_mode=False)
    assert exc.value.format_message() == f"Invalid value for {option}: 0 is not a finite number > 0"


def test_the_option_groups_reach_the_command_as_objects():
    from typer.testing import CliRunner

    res = CliRunner().invoke(
        _probe_app(), ["--field", "none", "-f", "json", "-o", "x.csv", "-q", "--workers", "3"]
    )
    assert res.exit_code == 0, res.output
    assert res.output.split() == ["json", "x.csv", "True", "3"]
    res = CliRunner().invoke(_probe_app(), ["--help"])
    for opt in (
        "--format",
        "--out",
        "--plot",
        "--quiet",
        "--debug",
        "--workers",
        "--scheduler",
        "--checkpoint",
    ):
        assert opt in res.output


def test_an_internal_error_before_any_command_carries_the_program_prefix(monkeypatch, capsys):
    def boom(name: str):
        raise RuntimeError("kaputt")

    monkeypatch.setattr(app_mod, "load_command", boom)
    rc = main(["encode", "gps"])
    err = capsys.readouterr().err
    assert rc == 1
    assert err.startswith("motionsig: internal error: RuntimeError: kaputt")


def test_an_internal_error_inside_a_command_carries_its_path(monkeypatch, capsys):
    def boom(self, table):
        raise RuntimeError("kaputt")

    monkeypatch.setattr(common.Output, "emit", boom)
    rc = main(["encode", "gps", "--prn", "1"])
    err = capsys.readouterr().err
    assert rc == 1
    assert err.startswith("motionsig encode gps: internal error: RuntimeError: kaputt"), err


def test_demo_outputs_reads_every_motionsig_line_of_the_demo_target():
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
    try:
        import demo_outputs
    finally:
        sys.path.pop(0)
    lines = demo_outputs.demo_lines(Path(__file__).resolve().parents[2] / "Makefile")
    text = (Path(__file__).resolve().parents[2] / "Makefile").read_text()
    demo = text.split("\ndemo:", 1)[1].split("\n\n", 1)[0]
    assert len(lines) == demo.count("\t@$(BIN)/motionsig ") + demo.count("\t$(BIN)/motionsig ") > 10
    # a reworded note is exempt from the comparison, a one-word parameter under the same key is not
    before = '# assumptions: "T, m_rho: spec"\n# radar: "origin"\n# x: {"radar": "origin", "note": "a b"}'
    after = '# assumptions: "assumed: T, m_rho"\n# radar: "origin"\n# x: {"radar": "origin", "note": "c d"}'
    assert demo_outputs._normalise(before) == demo_outputs._normalise(after)
    assert demo_outputs._normalise('# radar: "origin"') != demo_outputs._normalise('# radar: "sensor"')


def test_help_is_plain_text_and_keeps_bracketed_units(capsys):
    rc, out, _ = run(capsys, "track-sat", "simulate", "--help")
    assert rc == 0
    assert "[ns]" in out and "╭" not in out
