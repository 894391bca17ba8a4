"""The secret key that signs a checkpoint's task files: a checkpoint directory is untrusted input.

The index of a checkpoint records, for each task file, an HMAC-SHA256 under this key of the run's manifest
and the file's bytes (:class:`motionsig_cli.engine.Checkpoint`). Whoever can write the directory but does
not hold the key cannot make a run use a file of their choosing: a file and an index line forged, edited or
copied from another run fail the check and the task is recomputed. The key is

1. the text of the environment variable :data:`KEY_ENV`, if set and not empty (to share checkpoints
   between accounts or machines that do not share a home directory: give every run the same value); else
2. the file :data:`KEY_FILE` in the user's configuration directory (``$XDG_CONFIG_HOME/motionsig``, default
   ``~/.config/motionsig``), made on first use with 32 random bytes, readable by its owner only.

A key file that is not a regular file of the expected size, or that others may write, is refused by name.
"""

from __future__ import annotations

import os
import secrets
import stat
from pathlib import Path

from motionsig_cli.errors import InputError

__all__ = ["KEY_ENV", "KEY_FILE", "checkpoint_key", "key_path"]

KEY_ENV = "MOTIONSIG_CHECKPOINT_KEY"
KEY_FILE = "checkpoint.key"
_KEY_HEX = 64  # 32 random bytes, written in hex

_cached: dict[str, bytes] = {}


def key_path() -> Path:
    """Where the key file is: ``$XDG_CONFIG_HOME/motionsig/checkpoint.key`` (default ``~/.config``)."""
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "motionsig" / KEY_FILE


def checkpoint_key() -> bytes:
    """The key of this account (see the module docstring), made on first use.

    Raises:
        InputError: the key file cannot be made or read, is not a regular file of 64 hex digits, or others
            may write it.
    """
    text = os.environ.get(KEY_ENV, "")
    if text:
        return text.encode()
    path = key_path()
    if str(path) in _cached:
        return _cached[str(path)]
    try:
        path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
    except FileExistsError:
        key = _read(path)
    except OSError as exc:
        raise InputError(
            f"{path}: cannot make the checkpoint key ({exc.strerror or exc}); set {KEY_ENV}"
        ) from None
    else:
        key = secrets.token_hex(_KEY_HEX // 2).encode()
        with os.fdopen(fd, "wb") as fh:
            fh.write(key + b"\n")
    _cached[str(path)] = key
    return key


def _read(path: Path) -> bytes:
    """The key in an existing key file, checked before it is read."""
    try:
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{path}: the checkpoint key is not a regular file")
        if st.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            raise InputError(f"{path}: the checkpoint key may be written by others: chmod 600 it")
        if st.st_size > 2 * _KEY_HEX:
            raise InputError(f"{path}: the checkpoint key is {st.st_size} bytes, not {_KEY_HEX} hex digits")
        data = path.read_bytes().strip()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the checkpoint key ({exc.strerror or exc})") from None
    if len(data) != _KEY_HEX or any(c not in b"0123456789abcdef" for c in data):
        raise InputError(
            f"{path}: the checkpoint key is not {_KEY_HEX} hex digits; remove it to make a new one"
        )
    return data
