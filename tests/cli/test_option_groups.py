"""The option-group mechanism (:mod:`motionsig_cli.cli.option_groups`) and the shared record options:
a group's fields become the command's options (help, defaults), the parsed values reach the dataclass, a
clash of names is refused; every command that reads one record takes it as a positional FILE or ``-``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import pytest
import typer
from typer.testing import CliRunner

from motionsig_cli.cli.common import Output, command
from motionsig_cli.cli.option_groups import RecordOptions, given, options
from tests.cli.helpers import one_line_error, run


@dataclass(frozen=True)
class Noise:
    """A test group."""

    sigma: Annotated[float, typer.Option("--sigma", help="Noise sigma in metres.")] = 2.5
    label: Annotated[str | None, typer.Option("--label", help="A name.")] = None


def _app(fn) -> typer.Typer:
    app = typer.Typer()
    app.command()(fn)
    return app


def test_group_fields_are_options_with_help_and_defaults():
    seen = {}

    @options(noise=Noise)
    def cmd(
        count: Annotated[int, typer.Option("--count", help="How many.")] = 1, noise: Noise = Noise()
    ) -> None:
        seen.update(count=count, noise=noise)

    runner = CliRunner()
    help_text = runner.invoke(_app(cmd), ["--help"], env={"COLUMNS": "200"}).output
    assert "--sigma" in help_text and "Noise sigma in metres." in help_text and "2.5" in help_text
    assert help_text.index("--count") < help_text.index("--sigma") < help_text.index("--label")
    assert runner.invoke(_app(cmd), []).exit_code == 0
    assert seen == {"count": 1, "noise": Noise(2.5, None)}
    assert runner.invoke(_app(cmd), ["--sigma", "4", "--label", "x", "--count", "3"]).exit_code == 0
    assert seen == {"count": 3, "noise": Noise(4.0, "x")}
    assert given(seen["noise"]) == {"sigma": 4.0, "label": "x"}


def test_groups_work_under_command_with_output_options(capsys):
    seen = {}

    @command(plot=False)
    @options(noise=Noise)
    def cmd(noise: Noise, *, output: Output) -> None:
        seen.update(noise=noise, output=output)

    result = CliRunner().invoke(_app(cmd), ["--sigma", "7", "-q"])
    assert result.exit_code == 0, result.output
    assert seen["noise"].sigma == 7.0 and seen["output"].quiet


def test_a_clash_of_names_is_refused():
    with pytest.raises(TypeError, match="declares 'sigma'"):

        @options(noise=Noise)
        def cmd(noise: Noise, sigma: float = 1.0) -> None: ...

    with pytest.raises(TypeError, match="declares 'sigma'"):

        @options(a=Noise, b=Noise)
        def cmd2(a: Noise, b: Noise) -> None: ...

    with pytest.raises(TypeError, match="no parameter"):

        @options(noise=Noise)
        def cmd3() -> None: ...


def test_record_options_path():
    assert RecordOptions().path is None
    assert RecordOptions(file="a.csv").path == "a.csv"
    assert RecordOptions(input_file="-").path == "-"
    with pytest.raises(typer.BadParameter, match="not both"):
        _ = RecordOptions(file="a.csv", input_file="b.csv").path


def _record(capsys, tmp_path):
    rc, out, err = run(capsys, "maneuver", "--view", "measurements", "--runs", "1", "--sigma", "100",
                       "--scans", "40")  # fmt: skip
    assert rc == 0, err
    path = tmp_path / "rec.csv"
    path.write_text(out)
    return path


def test_maneuver_reads_file_stdin_and_the_old_input_option(capsys, tmp_path, monkeypatch):
    import io

    rec = _record(capsys, tmp_path)
    rc, by_file, err = run(capsys, "maneuver", str(rec), "--method", "imm,glr")
    assert rc == 0, err
    rc, by_option, err = run(capsys, "maneuver", "--input", str(rec), "--method", "imm,glr")
    assert rc == 0 and by_option == by_file, err
    monkeypatch.setattr("sys.stdin", io.StringIO(rec.read_text()))
    rc, by_stdin, err = run(capsys, "maneuver", "-", "--method", "imm,glr")
    assert rc == 0 and by_stdin.replace("source: -", "").count("\n") == by_file.count("\n"), err
    err = one_line_error(capsys, "maneuver", str(rec), "--input", str(rec))
    assert "--input" in err and "not both" in err


def test_maneuver_help_shows_file_not_the_deprecated_option(capsys):
    rc, out, _ = run(capsys, "maneuver", "--help")
    assert rc == 0 and "FILE" in out and "-i, --input" not in out


def test_slrt_reads_file_and_the_old_input_option(capsys, tmp_path):
    dets, sensors = tmp_path / "dets.csv", tmp_path / "sensors.csv"
    for view, path in (("detections", dets), ("sensors", sensors)):
        rc, _, err = run(capsys, "slrt", "--view", view, "--runs", "1", "--scans", "8", "-o", str(path), "-q")
        assert rc == 0, err
    rc, by_file, err = run(capsys, "slrt", str(dets), "--sensor-table", str(sensors), "-q")
    assert rc == 0, err
    rc, by_option, err = run(capsys, "slrt", "--input", str(dets), "--sensor-table", str(sensors), "-q")
    assert rc == 0 and by_option == by_file, err
    err = one_line_error(capsys, "slrt", str(dets), "-i", str(dets), "--sensor-table", str(sensors))
    assert "--input" in err and "not both" in err
