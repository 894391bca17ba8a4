"""Task files of a checkpoint are data, never code (issue 39): exact round trips, and crafted files refused."""

from __future__ import annotations

import json
import math
import struct
import sys

import numpy as np
import pytest

from motionsig_cli.maneuver.study import MCPartial
from motionsig_cli.modesig.baseline_calibration import _Outcomes
from motionsig_cli.modesig.baseline_roc import Outcomes
from motionsig_cli.modesig.lmp1d import TrialOutcomes
from motionsig_cli.modesig.lmp_search import Fig3Outcomes
from motionsig_cli.taskdata import MAGIC, TaskDataError, decode, encode


def _same(a, b) -> bool:
    """Equal in type, dtype, shape, memory order and bits, recursively."""
    if type(a) is not type(b):
        return False
    if isinstance(a, np.ndarray):
        return (
            a.dtype == b.dtype
            and a.shape == b.shape
            and a.flags.f_contiguous == b.flags.f_contiguous
            and a.flags.c_contiguous == b.flags.c_contiguous
            and a.tobytes(order="A") == b.tobytes(order="A")
        )
    if isinstance(a, np.generic):
        return a.dtype == b.dtype and a.tobytes() == b.tobytes()
    if isinstance(a, float):
        return struct.pack("<d", a) == struct.pack("<d", b)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    if hasattr(a, "__dataclass_fields__"):
        return all(_same(getattr(a, f), getattr(b, f)) for f in a.__dataclass_fields__)
    return a == b


RNG = np.random.default_rng(3)
RESULTS = [
    # what the jobs' run_task return: arrays, tuples of arrays, dicts of arrays, dataclasses of arrays
    RNG.standard_normal((3, 4)),
    np.asfortranarray(RNG.standard_normal((3, 4))),
    RNG.standard_normal((5, 6))[::2, 1::2],  # a strided view: stored as C order, values exact
    np.array([1, 2, 3], dtype=">i4"),
    np.zeros((0, 3), dtype=np.int64),
    np.array([True, False]),
    np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 5e-324, 1.7976931348623157e308]),
    np.array([1 + 2j], dtype=np.complex64),
    (np.arange(4, dtype=np.int64), np.ones(2), RNG.standard_normal(3), RNG.standard_normal(3)),
    {"gnn": RNG.standard_normal((2, 5)), "pda": RNG.standard_normal((2, 5))},
    {"ok": np.ones((2, 3, 4), bool), "lam_max": RNG.standard_normal((2, 3, 4)), "repairs": 7},
    (np.ones(3, np.int64), np.zeros(3, np.int64), 0),
    TrialOutcomes(np.ones((2, 3, 4), bool), np.zeros((2, 3, 4), bool), RNG.standard_normal((2, 3, 4))),
    TrialOutcomes(np.ones((1, 1, 1), bool), np.ones((1, 1, 1), bool), np.ones((1, 1, 1)), np.ones((1, 1, 1))),
    Outcomes(RNG.standard_normal((2, 3, 4)), np.ones((2, 3, 4), bool)),
    Fig3Outcomes(np.ones(3, bool), RNG.standard_normal(3)),
    _Outcomes(RNG.standard_normal((3, 2)), np.ones((3, 2), bool)),  # a module's private result class
    {
        "imm": MCPartial(
            np.ones((4, 2)), np.ones((4, 2)), None, None, np.ones((2, 4), bool), np.arange(8).reshape(2, 4)
        )
    },
    [1, -(10**30), 0.1, -0.0, math.nan, "text", None, True, np.float64(2.5), np.int64(-3), np.bool_(True)],
    {1: "a", (2, "b"): [()], 0.5: {}},
]


@pytest.mark.parametrize("result", RESULTS, ids=range(len(RESULTS)))
def test_every_kind_of_task_result_round_trips_bitwise(result):
    key, back = decode(encode("range(0, 3)", result))
    assert key == "range(0, 3)"
    if isinstance(result, np.ndarray) and not (result.flags.c_contiguous or result.flags.f_contiguous):
        result = np.ascontiguousarray(result)  # as pickle stores a strided view
    assert _same(result, back)
    if isinstance(back, np.ndarray):
        assert back.flags.writeable and back.flags.owndata  # as a pickled array: its own, writable memory


def test_what_it_cannot_store_is_a_type_error():
    for bad in (
        np.array([object()]),
        {1, 2},
        object(),
        np.ma.masked_array([1.0]),
        np.array([("a", 1)], "U1,i4"),
    ):
        with pytest.raises(TypeError):
            encode("k", bad)


def _file(tree, arrays=(), key="k", blobs=b""):
    header = json.dumps({"key": key, "tree": tree, "arrays": list(arrays)}).encode()
    return MAGIC + struct.pack("<Q", len(header)) + header + blobs


def test_crafted_files_are_refused_and_import_nothing():
    before = set(sys.modules)
    crafted = [
        b"\x80\x04\x95",  # a pickle
        MAGIC + b"\xff" * 8,  # a header length past the end
        _file({"dataclass": "os:system", "fields": {}}),
        _file({"dataclass": "subprocess:Popen", "fields": {"args": {"str": "touch x"}}}),
        _file({"dataclass": "motionsig_cli.not_a_module:X", "fields": {}}),
        _file({"dataclass": "motionsig_cli.engine:Engine.__init__", "fields": {}}),
        _file(
            {"dataclass": "motionsig_cli.modesig.lmp_search:Fig3Outcomes", "fields": {"ok": None}}
        ),  # a field short
        _file({"array": 0}, [{"dtype": "|O8", "shape": [1], "order": "C", "offset": 0}], blobs=b"\0" * 8),
        _file(
            {"array": 0}, [{"dtype": "<f8", "shape": [10**12], "order": "C", "offset": 0}], blobs=b"\0" * 8
        ),
        _file({"array": 0}, [{"dtype": "<f8", "shape": [2], "order": "C", "offset": 0}], blobs=b"\0" * 8),
        _file({"array": 0}, [{"dtype": "<f8", "shape": [1], "order": "C", "offset": 0}], blobs=b"\0" * 9),
        _file(
            {"list": [{"array": 0}, {"array": 0}]},
            [{"dtype": "<f8", "shape": [1], "order": "C", "offset": 0}],
            blobs=b"\0" * 8,
        ),
        _file({"int": "9" * 5000}),
        _file({"float": "not a float"}),
        _file({"dict": [[{"list": []}, None]]}),
        _file({"dict": [[{"tuple": [{"list": []}]}, None]]}),
        _file({"dict": [[{"str": "a"}, None], [{"str": "a"}, None]]}),
        _file(json.loads("[" * 50 + "]" * 50)),
        _file({"tuple": []}, key=5),
        MAGIC + struct.pack("<Q", 20) + b'{"key":"k","key":"k"}'[:20],
    ]
    deep = {"list": []}
    for _ in range(200):
        deep = {"list": [deep]}
    crafted.append(_file(deep))
    for data in crafted:
        with pytest.raises(TaskDataError):
            decode(data)
    assert set(sys.modules) == before  # a file never makes an import


def test_a_dataclass_is_built_without_running_its_code(monkeypatch):
    """No __init__ or __post_init__ of the class runs while a file is read."""
    calls = []
    monkeypatch.setattr(Fig3Outcomes, "__post_init__", lambda self: calls.append(1), raising=False)
    _, back = decode(encode("k", Fig3Outcomes(np.ones(2, bool), np.zeros(2))))
    assert calls == [] and isinstance(back, Fig3Outcomes)


def test_mutated_files_give_a_task_data_error_or_a_value():
    """Every single-byte change and every truncation of a real file: TaskDataError or a result, nothing else."""
    data = encode("range(0, 2)", {"a": (np.arange(3.0), 5, TrialOutcomes(np.ones((1, 2, 1), bool), np.ones((1, 2, 1), bool), np.ones((1, 2, 1))))})  # fmt: skip
    rng = np.random.default_rng(1)
    for i in range(len(data)):
        for v in (0, 0xFF, int(rng.integers(256))):
            try:
                decode(data[:i] + bytes([v]) + data[i + 1 :])
            except TaskDataError:
                pass
        with pytest.raises(TaskDataError):
            decode(data[:i])
