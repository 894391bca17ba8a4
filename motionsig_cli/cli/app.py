"""The ``motionsig`` typer application and its entry point.

``main`` runs the click command in non-standalone mode so that every failure is turned into
exactly one line on stderr, ``motionsig <command>: error: …``, with exit code 2 (``--debug``
re-raises with the traceback), and a closed downstream pipe (``motionsig … | head``) ends the
program quietly.

The commands are loaded lazily (:class:`LazyGroup`): ``motionsig --help`` imports none of them, and
``motionsig encode …`` imports the encode command and the core it needs, not SciPy's statistics or the
filter banks of the other commands.
"""

from __future__ import annotations

import importlib
import os
import signal
import sys
from collections.abc import Sequence
from typing import Any

import typer
from typer._click import exceptions as click_exceptions
from typer.core import TyperGroup
from typer.exceptions import Abort
from typer.main import get_command

from motionsig_cli import __version__
from motionsig_cli.cli.common import command_path, set_command_path
from motionsig_cli.cli.io import InputError

# name -> (module, attribute: a typer app or a command function, the summary of ``motionsig --help``);
# a test checks that each summary is the first line of the command's own help
COMMANDS: dict[str, tuple[str, str, str]] = {
    "encode": (
        "motionsig_cli.cli.encode",
        "app",
        "Gold codes, m-sequences, GPS C/A codes, Table I mode codes, correlations and mode signatures.",
    ),
    "simulate": (
        "motionsig_cli.cli.simulate",
        "simulate",
        "Closed-loop vehicle whose position reference carries a mode signature: 1-D (eqs 53-55, Fig 2) or "
        "2-D radar (eqs 59-60).",
    ),
    "detect": (
        "motionsig_cli.cli.detect",
        "detect",
        "LMP mode detector: Lambda(i,tau,f_c) = 2 J_H0 - J_H1,cos - J_H1,sin from a filter bank (eq 52).",
    ),
    "slrt": (
        "motionsig_cli.cli.slrt",
        "slrt",
        "Sequential likelihood ratio for track existence from several radars: the confirmation schemes of "
        "Govaers, Evaluation of Distributed Detection Methods for Agile Targets (Fraunhofer FKIE, slides).",
    ),
    "maneuver": (
        "motionsig_cli.cli.maneuver",
        "maneuver",
        "Maneuvering-target tracking: IMM of three Kalman filters, GLR and MLR maneuver detection.",
    ),
    "jam-bound": (
        "motionsig_cli.cli.jam_bound",
        "app",
        "Jamming bounds of the air-to-satellite-to-ground surveillance link (ATC-10 §2): N̄_FL / N̄_ADL curves, "
        "the jammer power that disables the system, Tables 1.1 and 2.1.",
    ),
    "mac-roc": (
        "motionsig_cli.cli.mac_roc",
        "app",
        "Detection under multiple-access noise (ATC-10 §3): ROC bounds (3.5.13)-(3.5.14), the exact and Monte "
        "Carlo ROC, the Gaussian ROC_g, the exponent Exp(Exp_g) and the time-bandwidth relation.",
    ),
    "track-sat": (
        "motionsig_cli.cli.track_sat",
        "app",
        "Satellite multilateration with clock tracking (ATC-10 §4): constellation constants, Tables 4.2/4.3, "
        "ψ(α) (Fig 4.1), RMS error curves (Figs 4.2/4.3) and a Monte Carlo of the estimators.",
    ),
}


def summary_of(help_text: str | None) -> str:
    """The first paragraph of a help text, joined into one line (never cut at a period: 'Fig. 3.3')."""
    first = (help_text or "").strip().split("\n\n")[0]
    return " ".join(line.strip() for line in first.splitlines() if line.strip() != "\b")


def _full_summaries(cmd: Any) -> Any:
    """Give every command of a group its full first help paragraph as its summary (click would cut it
    at the first period and at 45 characters)."""
    if getattr(cmd, "short_help", None) is None and cmd.help:
        cmd.short_help = summary_of(cmd.help)
    for sub in getattr(cmd, "commands", {}).values():
        _full_summaries(sub)
    return cmd


def load_command(name: str) -> Any:
    """The click command of ``name``, importing its module."""
    module, attr, _ = COMMANDS[name]
    obj = getattr(importlib.import_module(module), attr)
    if isinstance(obj, typer.Typer):
        obj.rich_markup_mode = None  # plain help, as the root's: rich markup would eat "[ns]", "[m/s]"
        cmd = get_command(obj)
    else:
        single = typer.Typer(rich_markup_mode=None, add_completion=False)
        single.command(name)(obj)
        cmd = get_command(single)
    cmd.name = name
    return _full_summaries(cmd)


class LazyGroup(TyperGroup):
    """The root group: commands are imported when they run (or when their own help is asked for)."""

    def list_commands(self, ctx: Any) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: Any, cmd_name: str) -> Any:
        if cmd_name not in COMMANDS:
            return None
        if cmd_name not in self.commands:
            self.commands[cmd_name] = load_command(cmd_name)
        return self.commands[cmd_name]

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        name, cmd, rest = super().resolve_command(ctx, args)
        if cmd is not None:
            set_command_path(f"motionsig {cmd.name}")
        return name, cmd, rest

    def format_commands(self, ctx: Any, formatter: Any) -> None:
        """The command list from :data:`COMMANDS`, without importing any command."""
        rows = [(name, summary) for name, (_, _, summary) in COMMANDS.items()]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


app = typer.Typer(
    name="motionsig",
    help="Detection and tracking with signatures (Gold-code mode signatures, LMP detection, SLRT, "
    "maneuver detection, ATC-10 surveillance analyses). Results go to stdout as CSV.",
    no_args_is_help=True,
    rich_markup_mode=None,
    pretty_exceptions_enable=False,
    add_completion=True,
    cls=LazyGroup,
    context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100},
)


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"motionsig {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version and exit."
    ),
) -> None:
    """motionsig — detection and tracking with signatures."""


def _silence_broken_pipe() -> None:
    """Point stdout at /dev/null so the interpreter's final flush cannot raise again."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def _terminate(signum: int, frame: object) -> None:
    """SIGTERM → SystemExit, so context managers run and no temporary file is left behind."""
    raise SystemExit(128 + signum)


def _plain(message: str) -> str:
    """An option error without the validator's wording (typer's choice check says "Value error, 'x' is
    not one of 'a', 'b'.")."""
    return message.replace("Value error, ", "")


MAX_ERROR_CHARS = 1000
"""Longest error message: a longer one (a 5,000-digit cell, 100,000 column names) keeps its start and its
end."""


def _one_line(message: str) -> str:
    """An error message as one line of at most :data:`MAX_ERROR_CHARS` characters (line breaks of a cell's
    text become spaces; the middle of a long message is cut, saying how long it was)."""
    text = " ".join(message.splitlines())
    if len(text) <= MAX_ERROR_CHARS:
        return text
    return f"{text[:700]} … ({len(text):,} characters) … {text[-200:]}"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the process exit code (0 ok, 2 bad input or usage, 1 internal error)."""
    args = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args
    set_command_path("motionsig")
    command = get_command(app)
    if argv is None:  # only as the real program, not when called from tests
        signal.signal(signal.SIGTERM, _terminate)
    try:
        rv = command.main(args=args, prog_name="motionsig", standalone_mode=False)
        sys.stdout.flush()
        return rv if isinstance(rv, int) else 0
    except BrokenPipeError:
        _silence_broken_pipe()
        return 0
    except SystemExit as exc:
        # typer's vendored click turns EPIPE into sys.exit(1) after wrapping the streams
        if type(sys.stdout).__name__ == "PacifyFlushWrapper":
            _silence_broken_pipe()
            return 0
        raise exc
    except click_exceptions.NoArgsIsHelpError as exc:
        typer.echo(exc.ctx.get_help() if exc.ctx else str(exc))
        return 0
    except click_exceptions.ClickException as exc:
        if debug:
            raise
        path = exc.ctx.command_path if getattr(exc, "ctx", None) else command_path()
        typer.echo(f"{path}: error: {_one_line(_plain(exc.format_message()))}", err=True)
        return 2
    except InputError as exc:
        if debug:
            raise
        typer.echo(f"{command_path()}: error: {_one_line(str(exc))}", err=True)
        return 2
    except Abort:
        typer.echo(f"{command_path()}: aborted", err=True)
        return 130
    except Exception as exc:  # a bug, not bad input: say so in one line, keep the traceback for --debug
        if debug:
            raise
        typer.echo(
            f"{command_path()}: internal error: {_one_line(f'{type(exc).__name__}: {exc}')} "
            "(rerun with --debug for the traceback)",
            err=True,
        )
        return 1


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
