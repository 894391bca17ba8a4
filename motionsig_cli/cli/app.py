"""The ``motionsig`` typer application and its entry point.

``main`` runs the click command in non-standalone mode so that every failure is turned into
exactly one line on stderr with exit code 2 (``--debug`` re-raises with the traceback), and a
closed downstream pipe (``motionsig … | head``) ends the program quietly.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Sequence

import typer
from typer._click import exceptions as click_exceptions
from typer.exceptions import Abort
from typer.main import get_command

from motionsig_cli import __version__
from motionsig_cli.cli import detect, encode, jam_bound, mac_roc, maneuver, simulate, slrt, track_sat
from motionsig_cli.cli.io import InputError

app = typer.Typer(
    name="motionsig",
    help="Detection and tracking with signatures (Gold-code mode signatures, LMP detection, SLRT, "
    "maneuver detection, ATC-10 surveillance analyses). Results go to stdout as CSV.",
    no_args_is_help=True,
    rich_markup_mode=None,
    pretty_exceptions_enable=False,
    add_completion=False,
    context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100},
)
app.add_typer(encode.app, name="encode")
app.command("simulate")(simulate.simulate)
app.command("detect")(detect.detect)
app.command("slrt")(slrt.slrt)
app.command("maneuver")(maneuver.maneuver)
app.add_typer(jam_bound.app, name="jam-bound")
app.add_typer(mac_roc.app, name="mac-roc")
app.add_typer(track_sat.app, name="track-sat")


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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the process exit code (0 ok, 2 bad input or usage, 1 internal error)."""
    args = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args
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
        path = exc.ctx.command_path if getattr(exc, "ctx", None) else "motionsig"
        sub = path.removeprefix("motionsig").strip()
        sub = f" {sub}" if sub else ""
        typer.echo(f"motionsig{sub}: error: {exc.format_message()}", err=True)
        return 2
    except InputError as exc:
        if debug:
            raise
        typer.echo(f"motionsig: error: {exc}", err=True)
        return 2
    except Abort:
        typer.echo("motionsig: aborted", err=True)
        return 130
    except Exception as exc:  # a bug, not bad input: say so in one line, keep the traceback for --debug
        if debug:
            raise
        typer.echo(
            f"motionsig: internal error: {type(exc).__name__}: {exc} (rerun with --debug for the traceback)",
            err=True,
        )
        return 1


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
