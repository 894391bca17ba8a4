"""The error of bad input data (a file, a line, a column), reported as one line with exit code 2.

A bad *parameter* is a :class:`motionsig_cli.config.ConfigError`; a bad *record* (a missing column, a
non-numeric cell at ``file:line``) is an :class:`InputError`. This module imports nothing, so the
command layer can name the error without loading NumPy.
"""

from __future__ import annotations

MAX_MESSAGE_CHARS = 1000
"""Longest message of an :class:`InputError` (a longer one is cut, saying how much was left out): a hostile
file must not turn one error line into a megabyte of text."""


class InputError(Exception):
    """Bad input data (a file, a line, a column): reported as one line, exit code 2.

    A message longer than :data:`MAX_MESSAGE_CHARS` is cut there (readers also summarise long lists
    themselves, e.g. a header of 100,000 column names).

    Examples:
        >>> from motionsig_cli import InputError
        >>> str(InputError("track.csv:3: column 'x': 'abc' is not a number"))
        "track.csv:3: column 'x': 'abc' is not a number"
    """

    def __init__(self, message: object = "", *args: object) -> None:
        if isinstance(message, str) and len(message) > MAX_MESSAGE_CHARS:
            cut = len(message) - MAX_MESSAGE_CHARS + 40
            message = f"{message[: MAX_MESSAGE_CHARS - 40]}… ({cut} more characters)"
        super().__init__(message, *args)
