"""Options and behaviour shared by every command: the option groups (output, plot, quiet/debug, seed,
workers/scheduler/checkpoint) declared once, the :func:`command` decorator that adds them to a command
and maps the core's :class:`~motionsig_cli.config.ConfigError` to the option that set the field, and
progress bars on stderr.

Nothing heavy is imported here at module level (no rich, no engine, no numpy): ``motionsig --help`` and
a small command start in a fraction of a second.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import inspect
import math
import os
import stat
import sys
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from motionsig_cli.cli.io import InputError, atomic_path, check_output_path
from motionsig_cli.config import ConfigError

if TYPE_CHECKING:
    from rich.console import Console
    from rich.progress import Progress

    from motionsig_cli.engine import Budget, Engine, MonteCarloJob

DEFAULT_SEED = 2008  # motionsig_cli.rng.DEFAULT_SEED (a test checks they agree; rng imports numpy)

T = TypeVar("T")


def choices(name: str, doc: str, *values: str, **named: str) -> type[StrEnum]:
    """The choices of an option: a StrEnum, which typer lists in ``--help`` and parses (the functional
    form of ``class Name(StrEnum)``, declared in one call).

    Each of ``values`` is a member named after it with ``_`` for ``-`` (``"h0-noise"`` → ``h0_noise``);
    ``named`` adds, after them, members whose value is not a name (``one_d="1d"``). The enum belongs to
    the calling module (it pickles by name) and has ``doc`` as its docstring.
    """
    members = [(value.replace("-", "_"), value) for value in values] + list(named.items())
    enum = StrEnum(name, members, module=sys._getframe(1).f_globals["__name__"])
    enum.__doc__ = doc
    return enum


CodesVariant = choices(
    "CodesVariant",
    "Table I codes: the corrected Gold codes (default) or the strings as printed in the mode-signature paper.",
    "corrected",
    "printed",
)
OutputFormat = choices("OutputFormat", "Table output format.", "csv", "json")


FormatOpt = Annotated[
    OutputFormat,
    typer.Option("--format", "-f", help="Output format (CSV carries '# key: value' provenance lines)."),
]
OutOpt = Annotated[
    Path | None,
    typer.Option("--out", "-o", help="Write the table to this file (atomically) instead of stdout."),
]
PlotOpt = Annotated[
    Path | None, typer.Option("--plot", help="Save a figure; format from the extension (.png, .svg, .pdf).")
]
QuietOpt = Annotated[bool, typer.Option("--quiet", "-q", help="No progress bars or summaries on stderr.")]
DebugOpt = Annotated[bool, typer.Option("--debug", help="Show the full traceback on errors.")]


def _seed(value: int) -> int:
    """``--seed``: NumPy's SeedSequence takes any integer >= 0."""
    if value < 0:
        raise typer.BadParameter(f"{value} is not an integer >= 0")
    return value


SeedOpt = Annotated[
    int,
    typer.Option("--seed", callback=_seed, help="Root seed; trial t draws from SeedSequence(seed) child t."),
]
DEFAULT_SEED_VALUE = DEFAULT_SEED

PLOT_SUFFIXES = (".png", ".svg", ".pdf")


def checked(option: str, fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    """Call ``fn``; a ValueError becomes a one-line usage error naming ``option`` (exit 2)."""
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        raise typer.BadParameter(str(exc), param_hint=option) from exc


def int_list(text: str, *, what: str = "value", max_count: int = 10_000) -> list[int]:
    """Parse ``'5'``, a range ``'3-11'`` or a list ``'1,5,7-9'`` into integers, in order, without repeats.

    Only ASCII digits are accepted; a range longer than ``max_count`` is refused before it is built.
    """
    out: list[int] = []
    for part in text.split(","):
        lo, sep, hi = part.strip().partition("-")
        if not (lo.isascii() and lo.isdigit()) or (sep and not (hi.isascii() and hi.isdigit())):
            raise ValueError(f"expected a {what}, a range like 3-11 or a list like 1,5,7-9; got {text!r}")
        a, b = int(lo), int(hi) if sep else int(lo)
        if b < a:
            raise ValueError(f"empty range {part.strip()!r}")
        if b - a + 1 + len(out) > max_count:
            raise ValueError(f"more than {max_count} {what}s requested")
        out.extend(range(a, b + 1))
    return list(dict.fromkeys(out))


def check_outputs(
    out: Path | None, plot: Path | None = None, *, extra: dict[str, Path | None] | None = None
) -> None:
    """Validate ``--out``, ``--plot`` and any further figure options (``extra``: option name → path) before
    any work is done: figure suffixes, existing directories, and no two options naming the same file."""
    figures = {"--plot": plot, **(extra or {})}
    for option, path in figures.items():
        if path is not None and path.suffix.lower() not in PLOT_SUFFIXES:
            raise typer.BadParameter(
                f"unsupported figure type {path.suffix or '(none)'!r}; use one of {', '.join(PLOT_SUFFIXES)}",
                param_hint=option,
            )
    targets = {"--out": out, **figures}
    for option, path in targets.items():
        try:
            check_output_path(path, option)
        except InputError as exc:
            raise typer.BadParameter(str(exc).removeprefix(f"{option}: "), param_hint=option) from None
    seen: dict[str, str] = {}
    for option, path in targets.items():
        if path is None:
            continue
        key = os.path.realpath(path)
        if key in seen:
            raise typer.BadParameter(f"is the same file as {seen[key]}", param_hint=option)
        seen[key] = option


# Parameters of a string value that name a file the command reads (a record, ``--codes FILE``,
# ``--code file:PATH``), and how an error names the positional ones.
_INPUT_TEXT = {
    "source": "the input record",
    "file": "the input record",
    "measurements": "the measurement record",
    "input_file": "",
    "codes": "",
    "code": "",
}
_NOT_INPUTS = frozenset({"out", "plot", "checkpoint"})


def _named_files(value: str, *, record: bool) -> Iterator[tuple[str, bool]]:
    """The paths a string option reads, and whether each must be a regular file: a record argument's
    value itself; of a code option, each ``file:PATH`` of a ``;`` list (which must be a regular file) and
    each bare value that names a file (a code set's spec otherwise)."""
    for part in value.split(";") if not record else [value]:
        part = part.strip() if not record else part
        explicit = part[:5].lower() == "file:"
        if explicit:
            part = part[5:]
        if part and part != "-" and (record or explicit or os.path.lexists(part)):
            yield part, record or explicit


def same_file(a: str | Path, b: str | Path) -> bool:
    """Whether two paths name one file (a link, ``..``, a hard link), never raising."""
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):
        return False


def _inputs(
    kwargs: Mapping[str, Any], params: Mapping[str, tuple[str, bool]]
) -> Iterator[tuple[str, str, str | Path, bool]]:
    """Each file the command reads: (option, how an error names it, path, whether it must be a regular
    file)."""
    for name, value in kwargs.items():
        if value is None or name in _NOT_INPUTS or name.startswith("plot_"):
            continue
        option, positional = params.get(name, ("--" + name.replace("_", "-"), False))
        what = (_INPUT_TEXT.get(name) if positional else "") or f"the {option} file"
        if isinstance(value, Path):
            yield option, what, value, str(value) != "-"
        elif isinstance(value, str) and name in _INPUT_TEXT:
            for path, regular in _named_files(value, record=name not in ("codes", "code")):
                yield option, what, path, regular


_SPECIAL: tuple[tuple[Callable[[int], bool], str], ...] = (
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a device"),
    (stat.S_ISBLK, "a device"),
    (stat.S_ISSOCK, "a socket"),
)


def refuse_special_inputs(kwargs: Mapping[str, Any], params: Mapping[str, tuple[str, bool]]) -> None:
    """Before any read: every file the command reads is a regular file (or ``-``, stdin). A FIFO would
    hang, ``/dev/zero`` would exhaust memory, a directory or a symbolic link loop cannot be read: each is
    refused by name, without opening it."""
    for option, _, path, regular in _inputs(kwargs, params):
        if not regular:
            continue
        try:
            mode = os.stat(path).st_mode
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise InputError(f"{path}: a symbolic link loop ({option})") from None
            continue  # missing, unreadable: the reader says so, naming the file
        if stat.S_ISDIR(mode):
            raise InputError(f"{path}: is a directory, not a file ({option})")
        if not stat.S_ISREG(mode):
            kind = next((k for test, k in _SPECIAL if test(mode)), "not a regular file")
            raise InputError(f"{path}: {kind}, not a regular file ({option}; give - to read stdin)")


def refuse_overwrite(kwargs: Mapping[str, Any], params: Mapping[str, tuple[str, bool]]) -> None:
    """Before any work: ``--out``, ``--plot`` and every ``--plot-*`` figure are checked
    (:func:`check_output_path`), and none may be a file the command reads — a record, ``--receivers``,
    ``--sensor-table``, ``--codes FILE``, ``--code file:PATH`` — which would destroy it. ``params``: each
    parameter's option name and whether it is positional."""
    outputs = {
        params.get(name, ("--" + name.replace("_", "-"), False))[0]: value
        for name, value in kwargs.items()
        if isinstance(value, Path) and (name in ("out", "plot") or name.startswith("plot_"))
    }
    if not outputs:
        return
    for option, path in outputs.items():
        try:
            check_output_path(path, option)
        except InputError as exc:
            raise typer.BadParameter(str(exc).removeprefix(f"{option}: "), param_hint=option) from None
    for _, what, path, _ in _inputs(kwargs, params):
        for out_option, target in outputs.items():
            if same_file(path, target):
                raise typer.BadParameter(f"is {what} ({str(path)!r})", param_hint=out_option)


def save_figure(fig: Any, path: Path) -> None:
    """Save a matplotlib Figure atomically with reproducible metadata."""
    suffix = path.suffix.lower()
    metadata = (
        {"Software": None}
        if suffix == ".png"
        else {"Creator": None, "Date": None}
        if suffix == ".svg"
        else {"CreationDate": None}
    )
    import matplotlib  # the command layer may import matplotlib; the core never does

    try:
        with (
            atomic_path(path) as tmp,
            matplotlib.rc_context({"svg.hashsalt": "motionsig"}),
        ):  # reproducible SVG ids
            fig.savefig(tmp, format=suffix[1:], dpi=150, metadata=metadata)
    except OSError as exc:
        raise InputError(f"{path}: cannot write the figure ({exc.strerror or exc})") from None


def stderr_console() -> Console:
    """Console on stderr for progress and summaries (never stdout, which carries data)."""
    from rich.console import Console

    return Console(stderr=True)


def note(message: str, quiet: bool) -> None:
    """A one-line summary on stderr (suppressed by --quiet)."""
    if not quiet:
        typer.echo(message, err=True)


@contextlib.contextmanager
def progress(quiet: bool) -> Iterator[Progress]:
    """Rich progress bar on stderr, shown whenever stderr is a terminal (stdout may be a pipe or a file:
    the bar never touches it) and ``quiet`` is off."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    show = not quiet and sys.stderr.isatty()
    bar = Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total}"),
        TimeElapsedColumn(),
        console=stderr_console(),
        transient=True,
        disable=not show,
    )
    with bar:
        yield bar


def float_list(text: str, *, what: str = "value") -> list[float]:
    """Parse a comma-separated list of floats (``'1e-1,1e-2'``)."""
    try:
        out = [float(p) for p in text.split(",") if p.strip()]
    except ValueError:
        raise ValueError(f"expected a comma-separated list of numbers ({what}); got {text!r}") from None
    if not out:
        raise ValueError(f"no {what} in {text!r}")
    if not all(math.isfinite(v) for v in out):
        raise ValueError(f"{what} must be finite; got {text!r}")
    return out


# ------------------------------------------------------------------ the Monte Carlo engine options
WorkersOpt = Annotated[
    int | None,
    typer.Option(
        "--workers",
        help="Worker processes, this one included (default: the machine's cores); with --scheduler local, "
        "this process and N-1 Dask workers (a remote scheduler brings its own).",
    ),
]
SchedulerOpt = Annotated[
    str | None,
    typer.Option(
        "--scheduler",
        help="Run on a Dask cluster: a scheduler address (tcp://host:port) or 'local' (a LocalCluster on "
        "127.0.0.1). Needs the dask extra: pip install 'motionsig_cli[dask]'.",
    ),
]
CheckpointOpt = Annotated[
    Path | None,
    typer.Option(
        "--checkpoint",
        help="Keep finished chunks in this directory; rerun with it to resume an interrupted run "
        "(same result as an uninterrupted one).",
    ),
]


def _max_minutes(value: float | None) -> float | None:
    if value is not None and not (value > 0 and math.isfinite(value)):
        raise typer.BadParameter(f"{value} is not a number of minutes > 0")
    return value


MaxMinutesOpt = Annotated[
    float | None,
    typer.Option(
        "--max-minutes",
        callback=_max_minutes,
        help="Refuse a run whose estimated wall time on the workers it has exceeds this many minutes "
        "(default: the command's own limit, 4 to 60 min); no limit with --checkpoint.",
    ),
]


def make_engine(workers: int | None, scheduler: str | None, checkpoint: Path | None) -> Engine:
    """The engine of ``--workers/--scheduler/--checkpoint`` (a bad value is a one-line usage error)."""
    from motionsig_cli.engine import Engine, EngineError, default_workers

    cores = default_workers()
    if workers is not None and workers > 4 * cores and (scheduler is None or scheduler == "local"):
        raise typer.BadParameter(
            f"{workers} processes on this machine's {cores} cores would only slow the run down; use at most "
            f"{4 * cores}",
            param_hint="--workers",
        )
    try:
        return Engine(cores if workers is None else workers, scheduler, checkpoint)
    except EngineError as exc:
        raise typer.BadParameter(exc.detail, param_hint=option_name(exc.field)) from None


@contextlib.contextmanager
def engine_session(engine: Engine, total: int, label: str, quiet: bool) -> Iterator[Callable[[int], None]]:
    """A progress callback (finished trials) for an engine run inside the ``with`` block.

    An engine error (scheduler unreachable, foreign checkpoint) is a one-line usage error naming the
    option; Ctrl-C is one line and exit code 130 (no output is written: commands write after the
    block), with a hint to resume when a checkpoint is kept.
    """
    from motionsig_cli.engine import EngineError, WorkerDied

    finished = [0]
    try:
        with progress(quiet) as bar:
            task = bar.add_task(label, total=total)

            def advance(n: int) -> None:
                finished[0] += n
                bar.advance(task, n)

            yield advance
    except EngineError as exc:
        raise typer.BadParameter(exc.detail, param_hint=option_name(exc.field)) from None
    except WorkerDied as exc:
        hint = _resume_hint(engine, "")
        typer.echo(f"{command_path()}: error: {exc} after {finished[0]}/{total} trials{hint}", err=True)
        raise typer.Exit(1) from None
    except MemoryError:  # in this process's own share of the tasks (a worker's comes back the same way)
        typer.echo(
            f"{command_path()}: error: out of memory after {finished[0]}/{total} trials (fewer --workers or a "
            "smaller run)",
            err=True,
        )
        raise typer.Exit(1) from None
    except KeyboardInterrupt:
        hint = _resume_hint(engine, " (--checkpoint DIR keeps finished chunks)")
        typer.echo(f"{command_path()}: interrupted after {finished[0]}/{total} trials{hint}", err=True)
        raise typer.Exit(130) from None


def _resume_hint(engine: Engine, otherwise: str) -> str:
    """How to resume an interrupted run: with the engine's checkpoint, else ``otherwise``."""
    if engine.checkpoint is None:
        return otherwise
    return f"; rerun with --checkpoint {engine.checkpoint} to resume"


@contextlib.contextmanager
def progress_bar(label: str, total: int, quiet: bool) -> Iterator[Callable[[int], None]]:
    """A progress callback (``advance(n)``) for a long single computation, drawn on stderr when it is a
    terminal (see :func:`progress`)."""
    with progress(quiet) as bar:
        task = bar.add_task(label, total=total)
        yield lambda n: bar.advance(task, n)


# ------------------------------------------------------------------------------ option groups
@dataclass(frozen=True)
class Output:
    """The output options every command shares: ``--format``, ``--out``, ``--plot``, ``--quiet``,
    ``--debug`` (``plot`` is None for a command without a figure)."""

    fmt: OutputFormat = OutputFormat.csv
    out: Path | None = None
    plot: Path | None = None
    quiet: bool = False
    debug: bool = False

    def check(self, **figures: Path | None) -> None:
        """Validate ``--out``, ``--plot`` and further figure options (``plot_scan=path`` → ``--plot-scan``)
        before any work is done."""
        check_outputs(self.out, self.plot, extra={"--" + k.replace("_", "-"): v for k, v in figures.items()})

    def emit(self, table: Any) -> None:
        """Write the table to ``--out`` (atomically) or stdout, in ``--format``."""
        from motionsig_cli.cli.io import emit

        emit(table, self.fmt.value, self.out)

    def figure(self, fig: Any, path: Path | None = None) -> None:
        """Save ``fig`` to ``path`` (default ``--plot``)."""
        target = self.plot if path is None else path
        if target is not None:
            save_figure(fig, target)

    def note(self, message: str) -> None:
        """A one-line summary on stderr (not with ``--quiet``)."""
        note(message, self.quiet)

    def refuse_input(self, path: str | Path | None, what: str) -> None:
        """``--out`` naming an input file (``path``; ``-``, stdin, and None name none) is a usage error
        naming --out: it "is ``what``"."""
        if self.out is None or path is None or str(path) == "-":
            return
        if same_file(path, self.out):
            raise typer.BadParameter(f"is {what} ({str(path)!r})", param_hint="--out")

    def result(self, result: Any, figure: str) -> None:
        """A Monte Carlo result: with ``--plot`` its figure (``figure``: the function of
        :mod:`motionsig_cli.plotting` that draws ``result.figure_data()``), then its table and summary."""
        if self.plot is not None:
            from motionsig_cli import plotting

            self.figure(getattr(plotting, figure)(*result.figure_data()))
        self.emit(result.table())
        self.note(result.summary())


@dataclass(frozen=True)
class Parallel:
    """Where a Monte Carlo runs and how long it may take: ``--workers``, ``--scheduler``, ``--checkpoint``,
    ``--max-minutes``."""

    workers: int | None = None
    scheduler: str | None = None
    checkpoint: Path | None = None
    max_minutes: float | None = None

    def engine(self) -> Engine:
        """The engine (a bad value is a one-line usage error naming the option)."""
        return make_engine(self.workers, self.scheduler, self.checkpoint)

    def budget(self) -> Budget:
        """The run-time limit of the command (:func:`motionsig_cli.engine.check_run_time`): the workers
        are counted only when an estimate exceeds the limit on one core."""
        from motionsig_cli.engine import Budget, available_workers

        def workers() -> int:
            engine = self.engine()
            try:
                return available_workers(engine)
            except Exception as exc:  # EngineError (no scheduler there), or Dask's own
                field = getattr(exc, "field", "scheduler")
                raise typer.BadParameter(
                    getattr(exc, "detail", str(exc)), param_hint=option_name(field)
                ) from None

        return Budget(self.max_minutes, self.checkpoint is not None, workers)


def run_job(job: MonteCarloJob[T], engine: Engine, label: str, quiet: bool) -> T:
    """Run a Monte Carlo job on ``engine`` with a progress bar of finished trials (errors and Ctrl-C as in
    :func:`engine_session`)."""
    from motionsig_cli.engine import job_trials
    from motionsig_cli.engine import run_job as engine_run_job

    with engine_session(engine, job_trials(job), label, quiet) as advance:
        return engine_run_job(job, engine, progress=advance)


_OUTPUT_PARAMS = {
    "fmt": (FormatOpt, OutputFormat.csv),
    "out": (OutOpt, None),
    "plot": (PlotOpt, None),
    "quiet": (QuietOpt, False),
    "debug": (DebugOpt, False),
}
_PARALLEL_PARAMS = {
    "workers": (WorkersOpt, None),
    "scheduler": (SchedulerOpt, None),
    "checkpoint": (CheckpointOpt, None),
    "max_minutes": (MaxMinutesOpt, None),
}

# Field names of the core's configurations whose option is not ``--`` + the name with ``-`` for ``_``.
OPTION_NAMES: dict[str, str] = {}

_current: list[str] = ["motionsig"]


def command_path() -> str:
    """``motionsig <command>`` of the command running now (``motionsig`` before one has started): every
    error line starts with it."""
    return _current[0]


def set_command_path(path: str) -> None:
    """Record the running command (the application does it before parsing a command's options)."""
    _current[0] = path


def option_name(field: str, options: Mapping[str, str] | None = None) -> str:
    """The option that sets a configuration field: ``options`` (the command's own names), then
    :data:`OPTION_NAMES`, then ``--`` + the field name with ``-`` for ``_``."""
    if options and field in options:
        return options[field]
    return OPTION_NAMES.get(field, "--" + field.replace("_", "-"))


def _param_names(cmd: Any) -> dict[str, tuple[str, bool]]:
    """Each parameter of a click command: its option name (an argument's metavar) and whether it is
    positional."""
    out: dict[str, tuple[str, bool]] = {}
    for p in getattr(cmd, "params", ()):
        positional = p.param_type_name == "argument"
        opts = [o for o in p.opts if o.startswith("--")] or p.opts
        out[p.name] = ((p.metavar or p.name.upper()) if positional else opts[0], positional)
    return out


def command(
    *,
    output: bool = True,
    plot: bool = True,
    parallel: bool = False,
    options: Mapping[str, str] | None = None,
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Declare a command: add the shared option groups and turn the core's :class:`ConfigError` into a
    one-line usage error naming the option.

    The command function takes ``output: Output`` (with ``output=True``) and ``parallel: Parallel``
    (with ``parallel=True``) in place of the groups' options, which are declared here once and appended
    to its own options. ``options`` maps a configuration field to the command's option where the default
    rule (``sigma_r`` → ``--sigma-r``) does not name it.
    """

    def decorate(fn: Callable[..., Any]) -> Callable[..., Any]:
        sig = inspect.signature(fn, eval_str=True)
        own = [p for n, p in sig.parameters.items() if n not in ("output", "parallel")]
        added: dict[str, tuple[Any, Any]] = {}
        if parallel:
            added |= _PARALLEL_PARAMS
        if output:
            added |= {k: v for k, v in _OUTPUT_PARAMS.items() if plot or k != "plot"}
        params = own + [
            inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=ann)
            for name, (ann, default) in added.items()
        ]
        params = [p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in params]

        @functools.wraps(fn)
        def wrapper(**kwargs: Any) -> Any:
            from typer._click.globals import get_current_context

            ctx = get_current_context(silent=True)
            if ctx is not None:
                set_command_path(ctx.command_path)
                names = _param_names(ctx.command)
                refuse_overwrite(kwargs, names)
                refuse_special_inputs(kwargs, names)
            extra: dict[str, Any] = {}
            if output:
                extra["output"] = Output(**{k: kwargs.pop(k) for k in list(kwargs) if k in _OUTPUT_PARAMS})
            if parallel:
                extra["parallel"] = Parallel(
                    **{k: kwargs.pop(k) for k in list(kwargs) if k in _PARALLEL_PARAMS}
                )
            limits = (
                extra["parallel"].budget() if parallel else None
            )  # run-time checks of the core use the workers, --max-minutes and --checkpoint
            try:
                if limits is None:
                    return fn(**kwargs, **extra)
                from motionsig_cli.engine import budget

                with budget(limits):
                    return fn(**kwargs, **extra)
            except ConfigError as exc:
                raise typer.BadParameter(exc.detail, param_hint=option_name(exc.field, options)) from None

        wrapper.__signature__ = sig.replace(parameters=params)  # type: ignore[attr-defined]
        wrapper.__annotations__ = {p.name: p.annotation for p in params}
        return wrapper

    return decorate
