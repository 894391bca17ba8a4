"""Task results as data, never code: the file format of a checkpoint's task files.

A checkpoint directory is untrusted input (it is shared between machines and people), so a task file
must not be able to run code when it is read, the way a pickle can. A task's result is written as

    b"MSTASK1\\n" + header length (8 bytes, little-endian) + header (JSON, UTF-8) + the arrays' bytes

where the header holds the task's description (``key``), the result as a tree of typed JSON nodes, and
for each array its dtype, shape, memory order and place in the data that follows. The nodes are

- ``null``, ``true``, ``false`` and ``{"str": s}``; ``{"int": "123"}`` (decimal text) and
  ``{"float": "0x1.8p+1"}`` (:meth:`float.hex`: exact, −0.0, ±inf and NaN included);
- ``{"list": [...]}``, ``{"tuple": [...]}`` and ``{"dict": [[key, value], ...]}`` (order and the keys'
  types kept);
- ``{"array": i}`` (an ``ndarray`` of booleans or numbers, its dtype, byte order and C or Fortran order
  kept) and ``{"scalar": i}`` (a NumPy scalar, stored as a 0-d array);
- ``{"dataclass": "module:QualName", "fields": {...}}``: an instance of a dataclass of this package.

:func:`decode` reads nothing but these: a dtype is a plain number type (no objects, no records), the
arrays must exactly fill the data, a dataclass must be one of this package's modules already imported
(nothing is imported on a file's say) with exactly its fields, and it is built without calling its
``__init__`` (no code of the class runs). Every round trip is bitwise: ``decode(encode(key, x))`` gives
``x`` back with the same types, dtypes, shapes, memory order and bits.

This module imports nothing of the package (a bottom-floor module).
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import struct
import sys
from typing import Any

import numpy as np

__all__ = ["MAGIC", "MAX_DEPTH", "TaskDataError", "decode", "encode"]

MAGIC = b"MSTASK1\n"
MAX_DEPTH = 64
"""Deepest nesting of a result's containers."""
MAX_HEADER_BYTES = 16 << 20
MAX_INT_DIGITS = 4000
_DTYPE = re.compile(r"[<>|](b1|[iu][1248]|f[248]|c(8|16))")
_PACKAGE = __name__.rpartition(".")[0] or __name__


class TaskDataError(ValueError):
    """A task file that is not a task result written by :func:`encode` (damaged, foreign or crafted)."""


def encode(key: str, result: Any) -> bytes:
    """The bytes of a task file holding ``result`` under the task description ``key``.

    Raises:
        TypeError: ``result`` holds a value this format does not store (an object array, a class of
            another package, a set …): a job's ``run_task`` must return only the types listed above.
    """
    arrays: list[np.ndarray] = []
    tree = _node(result, arrays, 0)
    meta: list[dict[str, Any]] = []
    blobs: list[bytes] = []
    offset = 0
    for a in arrays:
        order = "F" if a.flags.f_contiguous and not a.flags.c_contiguous else "C"  # as pickle keeps it
        data = a.tobytes(order=order)
        meta.append({"dtype": a.dtype.str, "shape": list(a.shape), "order": order, "offset": offset})
        blobs.append(data)
        offset += len(data)
    header = json.dumps({"key": key, "tree": tree, "arrays": meta}, separators=(",", ":")).encode()
    return MAGIC + struct.pack("<Q", len(header)) + header + b"".join(blobs)


def _node(x: Any, arrays: list[np.ndarray], depth: int) -> Any:
    if depth > MAX_DEPTH:
        raise TypeError(f"a task result nested deeper than {MAX_DEPTH} levels")
    if x is None or isinstance(x, bool):
        return x
    if type(x) is int:
        return {"int": str(x)}
    if type(x) is float:
        return {"float": x.hex()}
    if type(x) is str:
        return {"str": x}
    if type(x) in (list, tuple):
        return {type(x).__name__: [_node(v, arrays, depth + 1) for v in x]}
    if type(x) is dict:
        return {"dict": [[_node(k, arrays, depth + 1), _node(v, arrays, depth + 1)] for k, v in x.items()]}
    if type(x) is np.ndarray or isinstance(x, np.generic):
        a = np.asarray(x)
        if not _DTYPE.fullmatch(a.dtype.str):
            raise TypeError(f"an array of dtype {a.dtype} cannot be kept in a task file")
        arrays.append(a)
        return {"array" if type(x) is np.ndarray else "scalar": len(arrays) - 1}
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        cls = type(x)
        if not cls.__module__.startswith(_PACKAGE + ".") or "<" in cls.__qualname__:
            raise TypeError(f"{cls.__module__}.{cls.__qualname__} is not a dataclass of this package")
        fields = {f.name: _node(getattr(x, f.name), arrays, depth + 1) for f in dataclasses.fields(x)}
        return {"dataclass": f"{cls.__module__}:{cls.__qualname__}", "fields": fields}
    raise TypeError(f"a {type(x).__name__} cannot be kept in a task file")


def decode(data: bytes) -> tuple[str, Any]:
    """(key, result) of a task file's bytes.

    Raises:
        TaskDataError: anything but a file :func:`encode` writes (the reason in the message).
    """
    if not data.startswith(MAGIC):
        raise TaskDataError("not a task file of this version (no MSTASK1 mark)")
    start = len(MAGIC) + 8
    if len(data) < start:
        raise TaskDataError("truncated header")
    (n,) = struct.unpack("<Q", data[len(MAGIC) : start])
    if n > MAX_HEADER_BYTES or start + n > len(data):
        raise TaskDataError("bad header length")
    try:
        header = json.loads(
            data[start : start + n].decode("utf-8"),
            parse_constant=_no_constant,
            parse_int=_bounded_int,
            object_pairs_hook=_unique_keys,
        )
    except (ValueError, RecursionError) as exc:
        raise TaskDataError(f"bad header ({exc})") from None
    if not isinstance(header, dict) or set(header) != {"key", "tree", "arrays"}:
        raise TaskDataError("bad header (not key, tree and arrays)")
    key = header["key"]
    if not isinstance(key, str) or not isinstance(header["arrays"], list):
        raise TaskDataError("bad header (key or arrays)")
    body = memoryview(data)[start + n :]
    arrays = _arrays(header["arrays"], body)
    used: set[int] = set()
    try:
        result = _value(header["tree"], arrays, used, 0)
    except RecursionError:
        raise TaskDataError("nested too deeply") from None
    except TypeError as exc:  # an unhashable dict key (a tuple holding a list)
        raise TaskDataError(f"bad value ({exc})") from None
    if len(used) != len(arrays):
        raise TaskDataError("an array is stored but not used")
    return key, result


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


def _bounded_int(text: str) -> int:
    if len(text) > 20:
        raise ValueError("an integer of more than 20 digits in the header")
    return int(text)


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out = dict(pairs)
    if len(out) != len(pairs):
        raise ValueError("a key repeats")
    return out


def _arrays(specs: list[Any], body: memoryview) -> list[np.ndarray]:
    out: list[np.ndarray] = []
    offset = 0
    for spec in specs:
        if not (isinstance(spec, dict) and set(spec) == {"dtype", "shape", "order", "offset"}):
            raise TaskDataError("bad array entry")
        dtype, shape, order = spec["dtype"], spec["shape"], spec["order"]
        if not (isinstance(dtype, str) and _DTYPE.fullmatch(dtype)):
            raise TaskDataError(f"dtype {str(dtype)[:20]!r} is not a plain number type")
        if not (
            isinstance(shape, list)
            and len(shape) <= 32
            and all(type(d) is int and 0 <= d < 1 << 40 for d in shape)
        ):
            raise TaskDataError("bad array shape")
        if order not in ("C", "F") or spec["offset"] != offset:
            raise TaskDataError("bad array order or offset")
        dt = np.dtype(dtype)
        count = math.prod(shape)
        nbytes = count * dt.itemsize
        if offset + nbytes > len(body):
            raise TaskDataError("the arrays run past the end of the file")
        flat = np.frombuffer(body, dtype=dt, count=count, offset=offset)
        out.append(flat.reshape(shape, order=order).copy(order="K"))  # its own, writable memory
        offset += nbytes
    if offset != len(body):
        raise TaskDataError("bytes after the last array")
    return out


def _value(node: Any, arrays: list[np.ndarray], used: set[int], depth: int) -> Any:
    if depth > MAX_DEPTH:
        raise TaskDataError(f"nested deeper than {MAX_DEPTH} levels")
    if node is None or isinstance(node, bool):
        return node
    if not (isinstance(node, dict) and len(node) in (1, 2)):
        raise TaskDataError("bad node")
    (tag, arg), *rest = node.items()
    if tag == "int" and not rest and isinstance(arg, str) and re.fullmatch(r"-?[0-9]{1,4000}", arg):
        return int(arg)
    if tag == "float" and not rest and isinstance(arg, str) and len(arg) <= 40:
        try:
            return float.fromhex(arg)
        except (ValueError, OverflowError):
            raise TaskDataError("bad float") from None
    if tag == "str" and not rest and isinstance(arg, str):
        return arg
    if tag in ("list", "tuple") and not rest and isinstance(arg, list):
        items = [_value(v, arrays, used, depth + 1) for v in arg]
        return items if tag == "list" else tuple(items)
    if tag == "dict" and not rest and isinstance(arg, list):
        out: dict[Any, Any] = {}
        for pair in arg:
            if not (isinstance(pair, list) and len(pair) == 2):
                raise TaskDataError("bad dict entry")
            k = _value(pair[0], arrays, used, depth + 1)
            if isinstance(k, (list, dict, np.ndarray)) or k in out:
                raise TaskDataError("bad or repeated dict key")
            out[k] = _value(pair[1], arrays, used, depth + 1)
        return out
    if tag in ("array", "scalar") and not rest and type(arg) is int and 0 <= arg < len(arrays):
        if arg in used:
            raise TaskDataError("an array is used twice")
        used.add(arg)
        a = arrays[arg]
        if tag == "scalar":
            if a.ndim:
                raise TaskDataError("a scalar that is not 0-d")
            return a[()]
        return a
    if tag == "dataclass" and rest and rest[0][0] == "fields" and isinstance(arg, str):
        fields = rest[0][1]
        if not isinstance(fields, dict):
            raise TaskDataError("bad dataclass fields")
        cls = _dataclass(arg)
        names = [f.name for f in dataclasses.fields(cls)]
        if sorted(names) != sorted(fields):
            raise TaskDataError(f"the fields of {arg} differ")
        obj = object.__new__(cls)
        for name in names:  # object.__setattr__: no __init__, __post_init__ or __setattr__ of the class runs
            object.__setattr__(obj, name, _value(fields[name], arrays, used, depth + 1))
        return obj
    raise TaskDataError("bad node")


def _dataclass(name: str) -> type:
    """A dataclass of this package, from a module already imported (a file never makes this import)."""
    module, sep, qualname = name.partition(":")
    if not sep or not module.startswith(_PACKAGE + ".") or not re.fullmatch(r"[A-Za-z_][\w.]*", qualname):
        raise TaskDataError(f"{name[:80]!r} is not a dataclass of this package")
    obj: Any = sys.modules.get(module)
    for part in qualname.split("."):
        obj = getattr(obj, part, None) if obj is not None and not part.startswith("__") else None
    if not (isinstance(obj, type) and dataclasses.is_dataclass(obj) and obj.__module__ == module):
        raise TaskDataError(f"{name[:80]!r} is not a dataclass of this package")
    return obj
