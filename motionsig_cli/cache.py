"""A per-process cache of measurement-independent results, bounded in bytes (least recently used first out).

A Monte Carlo task computes a bank's Riccati recursion, its replicas and their structure before it reads a
single record; every task of a run at the same measurement variance computes the same ones. A process that
runs several tasks of a run keeps them here, so that only its first task at each variance pays for them
(a 1-D bank task's fixed cost at N = 1600 fell from ≈ 0.097 s to ≈ 0.045 s), and tasks can be small enough to
balance the workers at the end of a run. What a task computes never depends on whether it was a hit.

Entries are read-only (their arrays are flagged so): a caller that wrote into one would change the next
task's result, and gets an error instead.
"""

from __future__ import annotations

import hashlib
import os
import threading
import weakref
from collections import OrderedDict
from collections.abc import Callable, Iterable
from typing import Any, Generic, TypeVar

import numpy as np

T = TypeVar("T")

_ALL: weakref.WeakSet[BytesLRU[Any]] = weakref.WeakSet()

DEFAULT_BYTES = 256 * 2**20
"""The bound of each cache [bytes] (``$MOTIONSIG_CACHE_MB`` sets it in MiB; 0 turns caching off)."""


def cache_bytes() -> int:
    """:data:`DEFAULT_BYTES`, or ``$MOTIONSIG_CACHE_MB`` MiB (a number ≥ 0; anything else: the default)."""
    text = os.environ.get("MOTIONSIG_CACHE_MB")
    try:
        mb = float(text) if text else None
    except ValueError:
        mb = None
    return DEFAULT_BYTES if mb is None or not mb >= 0 else int(mb * 2**20)


def key_of(*parts: Any) -> str:
    """A digest of ``parts``: arrays by dtype, shape and bytes, anything else by its ``repr`` (frozen
    dataclasses, numbers, tuples)."""
    h = hashlib.sha256()
    for p in parts:
        if isinstance(p, np.ndarray):
            a = np.ascontiguousarray(p)
            h.update(f"array{a.dtype.str}{a.shape}".encode())
            h.update(a.tobytes())
        else:
            h.update(repr(p).encode())
        h.update(b"\x1f")
    return h.hexdigest()


def freeze(arrays: Iterable[np.ndarray]) -> int:
    """Flag ``arrays`` read-only; their total size [bytes]."""
    total = 0
    for a in arrays:
        a.setflags(write=False)
        total += a.nbytes
    return total


def clear_all() -> None:
    """Empty every cache of this process (benchmarks and tests: a run from a cold start)."""
    for c in list(_ALL):
        c.clear()


class BytesLRU(Generic[T]):
    """``get(key, build)``: the value kept under ``key``, else ``build()`` kept under it.

    ``build`` returns ``(value, nbytes)``; a value larger than the bound is returned and not kept, and the
    least recently used values go until the rest fit. Safe to share between threads (two threads that miss
    the same key may both build it; the second one's value is kept).
    """

    def __init__(self, max_bytes: Callable[[], int] = cache_bytes) -> None:
        self._max = max_bytes
        self._items: OrderedDict[str, tuple[T, int]] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0
        _ALL.add(self)

    def get(self, key: str, build: Callable[[], tuple[T, int]]) -> tuple[T, bool]:
        """(value, hit)."""
        with self._lock:
            item = self._items.get(key)
            if item is not None:
                self._items.move_to_end(key)
                self.hits += 1
                return item[0], True
            self.misses += 1
        value, size = build()
        limit = self._max()
        with self._lock:
            if size <= limit:
                old = self._items.pop(key, None)
                if old is not None:
                    self._bytes -= old[1]
                self._items[key] = (value, size)
                self._bytes += size
                while self._bytes > limit and self._items:
                    _, (_, s) = self._items.popitem(last=False)
                    self._bytes -= s
        return value, False

    def clear(self) -> None:
        with self._lock:
            self._items.clear()
            self._bytes = 0

    def __len__(self) -> int:
        return len(self._items)

    @property
    def nbytes(self) -> int:
        return self._bytes
