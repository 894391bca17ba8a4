"""The error of bad input data (a file, a line, a column), reported as one line with exit code 2.

A bad *parameter* is a :class:`motionsig_cli.config.ConfigError`; a bad *record* (a missing column, a
non-numeric cell at ``file:line``) is an :class:`InputError`. This module imports nothing, so the
command layer can name the error without loading NumPy.
"""

from __future__ import annotations


class InputError(Exception):
    """Bad input data (a file, a line, a column): reported as one line, exit code 2.

    Examples:
        >>> from motionsig_cli import InputError
        >>> str(InputError("track.csv:3: column 'x': 'abc' is not a number"))
        "track.csv:3: column 'x': 'abc' is not a number"
    """
