"""Option groups declared once and shared by commands.

An option group is a frozen dataclass whose fields carry the typer declarations
(``Annotated[str | None, typer.Option("--columns", help=...)]``) and the defaults. :func:`options` splices
a group's fields into a command's signature (``__signature__``, which typer reads) in place of one
parameter, and rebuilds the dataclass from the parsed values, so the command takes the group as one
argument::

    @dataclass(frozen=True)
    class RecordOptions:
        columns: ColumnsOpt = None
        units: UnitsOpt = None

    @command()
    @options(record=RecordOptions)
    def track(record: RecordOptions, *, output: Output) -> None: ...

A field's name is the command's parameter name (``ctx.get_parameter_source(name)`` keeps working); a name
that the command or another group also declares is refused when the module is imported.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import typing
from collections.abc import Callable
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])


def group_parameters(group: type) -> list[inspect.Parameter]:
    """The command parameters of an option-group dataclass: one keyword-only parameter per field, with the
    field's ``Annotated`` declaration and default."""
    if not (dataclasses.is_dataclass(group) and isinstance(group, type)):
        raise TypeError(f"an option group is a dataclass, not {group!r}")
    hints = typing.get_type_hints(group, include_extras=True)
    params = []
    for field in dataclasses.fields(group):
        if field.default is not dataclasses.MISSING:
            default: Any = field.default
        elif field.default_factory is not dataclasses.MISSING:
            default = field.default_factory()
        else:
            default = inspect.Parameter.empty
        params.append(
            inspect.Parameter(
                field.name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=hints[field.name]
            )
        )
    return params


def options(**groups: type) -> Callable[[F], F]:
    """Replace each parameter ``name`` of the command by the fields of ``groups[name]`` (declared in its
    place, so ``--help`` keeps their order) and pass the command ``name=groups[name](**values)``.

    A field whose name is also a parameter of the command, or a field of another group, is a TypeError.
    """

    def decorate(fn: F) -> F:
        sig = inspect.signature(fn, eval_str=True)
        missing = [name for name in groups if name not in sig.parameters]
        if missing:
            raise TypeError(f"{fn.__name__}: no parameter {missing[0]!r} for its option group")
        owners = {name: f"{fn.__name__}()" for name in sig.parameters if name not in groups}
        fields: dict[str, list[str]] = {}
        params: list[inspect.Parameter] = []
        for name, param in sig.parameters.items():
            if name not in groups:
                params.append(param.replace(kind=inspect.Parameter.KEYWORD_ONLY))
                continue
            spliced = group_parameters(groups[name])
            for p in spliced:
                if p.name in owners:
                    raise TypeError(
                        f"{fn.__name__}: option group {groups[name].__name__} declares {p.name!r}, which "
                        f"{owners[p.name]} declares too"
                    )
                owners[p.name] = groups[name].__name__
            fields[name] = [p.name for p in spliced]
            params.extend(spliced)

        @functools.wraps(fn)
        def wrapper(**kwargs: Any) -> Any:
            for name, group in groups.items():
                kwargs[name] = group(
                    **{field: kwargs.pop(field) for field in fields[name] if field in kwargs}
                )
            return fn(**kwargs)

        wrapper.__signature__ = sig.replace(parameters=params)  # type: ignore[attr-defined]
        wrapper.__annotations__ = {p.name: p.annotation for p in params}
        return wrapper  # type: ignore[return-value]

    return decorate


def given(group: Any) -> dict[str, Any]:
    """The fields of an option group that are not None (the options given, where None is the default)."""
    return {k: v for k, v in dataclasses.asdict(group).items() if v is not None}


# --------------------------------------------------------------------------- groups shared by commands
import typer  # noqa: E402  (the mechanism above needs no typer; the groups below declare options)

FileArg = typing.Annotated[
    str | None,
    typer.Argument(
        metavar="FILE",
        help="The record to read instead of simulating: CSV or JSON (as the commands write it), '-' for stdin.",
        show_default=False,
    ),
]
InputAliasOpt = typing.Annotated[
    str | None, typer.Option("--input", "-i", hidden=True, help="Deprecated spelling of FILE.")
]
ColumnsOpt = typing.Annotated[
    str | None,
    typer.Option(
        "--columns", help="With FILE: which column is which role, role=name,... (e.g. time=Timestamp)."
    ),
]
UnitsOpt = typing.Annotated[
    str | None,
    typer.Option(
        "--units",
        help="With FILE: units of the columns, role=unit,... (e.g. x=km,time=ms); over the header's "
        "'name [unit]' and the metadata, else m, rad, s.",
    ),
]


@dataclasses.dataclass(frozen=True)
class RecordOptions:
    """How a command that reads one record takes it: a positional FILE (``-``: stdin), or the deprecated
    hidden ``--input FILE``, and the record's ``--columns`` and ``--units``."""

    file: FileArg = None
    input_file: InputAliasOpt = None
    columns: ColumnsOpt = None
    units: UnitsOpt = None

    @property
    def path(self) -> str | None:
        """FILE, or ``--input``'s (None: no record); both given is a usage error naming ``--input``."""
        if self.file is not None and self.input_file is not None:
            raise typer.BadParameter(
                f"is the old spelling of FILE: give {self.file!r} or --input {self.input_file!r}, not both",
                param_hint="--input",
            )
        return self.file if self.file is not None else self.input_file

    def refuse_without_file(self) -> None:
        """``--columns`` and ``--units`` describe a record: a usage error when none is read."""
        for name, value in (("--columns", self.columns), ("--units", self.units)):
            if value is not None:
                raise typer.BadParameter("describes the record; give FILE (or --input FILE)", param_hint=name)
