"""Checked configurations: one error type for a bad parameter, and the checks the dataclasses use.

Every frozen configuration of the core checks its own fields in ``__post_init__`` and raises
:class:`ConfigError`, which names the field and the bad value. It is a :class:`ValueError`, so code
that catches ``ValueError`` keeps working. The command layer maps ``field`` to its option name
(``sigma_r`` → ``--sigma-r``) and prints one line; it never checks a range itself.

    >>> from motionsig_cli.config import in_range
    >>> in_range("p_d", 1.5, 0.0, 1.0, lo_open=True)
    Traceback (most recent call last):
    ...
    motionsig_cli.config.ConfigError: p_d = 1.5 is not in (0, 1]
"""

from __future__ import annotations

import math
import operator
from collections.abc import Collection
from typing import Any


class ConfigError(ValueError):
    """A bad configuration value.

    Attributes:
        field: The field (dataclass attribute or function argument) that holds the bad value.
        value: The bad value.
        reason: What is wrong, without the field's name (``"is not in (0, 1]"``).

    Examples:
        >>> from motionsig_cli import ConfigError
        >>> exc = ConfigError("sigma", -1.0, "is not > 0")
        >>> str(exc), exc.field, exc.value, isinstance(exc, ValueError)
        ('sigma = -1 is not > 0', 'sigma', -1.0, True)
    """

    def __init__(self, field: str, value: Any, reason: str) -> None:
        self.field = field
        self.value = value
        self.reason = reason
        super().__init__(f"{field} = {_show(value)} {reason}")

    @property
    def detail(self) -> str:
        """The message without the field's name, for a caller that names the field its own way
        (the command line names the option)."""
        return f"{_show(self.value)} {self.reason}"


def _show(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, tuple | list) and len(value) > 8:
        return f"{type(value).__name__} of {len(value)}"
    return str(value)


def _fmt(x: float) -> str:
    return "inf" if x == math.inf else "-inf" if x == -math.inf else f"{x:g}"


def in_range(
    field: str,
    value: float,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
) -> float:
    """``value`` if it is a finite number in the interval, else :class:`ConfigError`.

    Infinite bounds are open; ``unit`` is appended to the interval in the message.
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ConfigError(field, value, "is not a number") from None
    ok = math.isfinite(x) and (x > lo if lo_open else x >= lo) and (x < hi if hi_open else x <= hi)
    if not ok:
        left = "(" if lo_open or lo == -math.inf else "["
        right = ")" if hi_open or hi == math.inf else "]"
        where = f"{left}{_fmt(lo)}, {_fmt(hi)}{right}"
        if lo == 0 and lo_open and hi == math.inf:
            where = "a finite number > 0"
            raise ConfigError(field, value, f"is not {where}{f' {unit}' if unit else ''}")
        raise ConfigError(field, value, f"is not in {where}{f' {unit}' if unit else ''}")
    return x


def positive(field: str, value: float, *, unit: str = "") -> float:
    """A finite number > 0."""
    return in_range(field, value, 0.0, lo_open=True, unit=unit)


def integer(field: str, value: Any, lo: int | None = None, hi: int | None = None) -> int:
    """An integer (not a bool) in [lo, hi]."""
    if isinstance(value, bool):
        raise ConfigError(field, value, "is not an integer")
    try:
        n = operator.index(value)  # int and NumPy integers
    except TypeError:
        if not (isinstance(value, float) and math.isfinite(value) and value == int(value)):
            raise ConfigError(field, value, "is not an integer") from None
        n = int(value)  # an integral float, 3.0
    if (lo is not None and n < lo) or (hi is not None and n > hi):
        lo_s = "-inf" if lo is None else str(lo)
        hi_s = "inf" if hi is None else str(hi)
        raise ConfigError(field, value, f"is not in [{lo_s}, {hi_s}]")
    return n


def one_of(field: str, value: Any, choices: Collection[Any]) -> Any:
    """``value`` if it is one of ``choices``."""
    if value not in choices:
        raise ConfigError(field, value, f"is not one of {', '.join(map(str, choices))}")
    return value
