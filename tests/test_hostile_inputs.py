"""Hostile files for the readers every command uses (issue 39): special files refused by name before any read,
every reader bounded in bytes, JSON limits enforced before parsing, only ASCII decimal numbers, and a fuzz
whose every case ends in a valid result or one :class:`InputError`, under a memory bound."""

from __future__ import annotations

import contextlib
import io
import json
import os
import signal
import sys
import tracemalloc

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionsig_cli.errors import MAX_MESSAGE_CHARS, InputError
from motionsig_cli.records import RecordSpec, Role, read_record
from motionsig_cli.tables import MAX_LINE_BYTES, read_table

SPEC = RecordSpec(
    (
        Role("time", aliases=("t",), kind="time", order="increasing"),
        Role("x", quantity="length", missing=True),
        Role("n", kind="integer", required=False),
        Role("label", kind="label", required=False),
    ),
    max_rows=50,
)


@contextlib.contextmanager
def _deadline(seconds: int = 10):
    """Fail instead of hanging (a FIFO that blocks the reader)."""

    def boom(*_):
        raise TimeoutError("the reader blocked")

    old = signal.signal(signal.SIGALRM, boom)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@contextlib.contextmanager
def _peak(limit_mb: float):
    """Assert the Python and NumPy allocations inside the block peak below ``limit_mb``."""
    tracemalloc.start()
    try:
        yield
    finally:
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert peak < limit_mb * 2**20, f"peak {peak / 2**20:.1f} MiB"


def _refused(source, match: str, **kw) -> str:
    with _deadline(), pytest.raises(InputError, match=match) as exc:
        read_table(source, **kw)
    return str(exc.value)


# ------------------------------------------------------------------------------------ special files
def test_special_files_are_refused_by_name_before_any_read(tmp_path):
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)  # no writer: opening it for reading would block
    assert _refused(fifo, r"fifo\.csv: is a FIFO").startswith(str(fifo))
    _refused("/dev/zero", r"/dev/zero: is a character device")
    _refused(tmp_path, r"is a directory")
    loop = tmp_path / "loop.csv"
    loop.symlink_to(loop)
    _refused(loop, r"loop\.csv: cannot read \(a symbolic link loop")
    _refused(tmp_path / "none.csv", r"none\.csv: cannot read \(No such file")
    link = tmp_path / "link.csv"
    link.symlink_to(fifo)
    _refused(link, r"link\.csv: is a FIFO")  # a link is followed, and what it names checked


class _Endless(io.RawIOBase):
    """Standard input that never ends: ``/dev/zero`` or a generator of rows."""

    def __init__(self, chunk: bytes) -> None:
        self.chunk = chunk

    def readable(self) -> bool:
        return True

    def readinto(self, b) -> int:
        n = len(b)
        data = (self.chunk * (n // len(self.chunk) + 1))[:n]
        b[:n] = data
        return n


def _stdin(monkeypatch, raw) -> None:
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BufferedReader(raw)))


def test_endless_stdin_is_bounded(monkeypatch):
    """``detect - < /dev/zero``: refused at the first over-long line, having held a few MiB; endless rows
    are refused at the byte limit (or the row limit)."""
    _stdin(monkeypatch, _Endless(b"\0"))
    with _peak(4 * MAX_LINE_BYTES / 2**20 + 8):
        _refused("-", rf"<stdin>:1: a line longer than {MAX_LINE_BYTES} bytes")
    _stdin(monkeypatch, _Endless(b"1,2\n"))
    _refused("-", r"<stdin>: larger than 1000000 bytes", max_bytes=1_000_000, max_rows=10**9)
    _stdin(monkeypatch, _Endless(b"1,2\n"))
    _refused("-", r"<stdin>:1002: more than 1000 data rows", max_rows=1000)


# ---------------------------------------------------------------------------------------------- JSON
def test_json_limits_are_enforced_before_parsing(tmp_path, monkeypatch):
    p = tmp_path / "t.json"
    p.write_text("[" * 100_000 + "]" * 100_000)
    _refused(p, r"t\.json: JSON nested deeper than 64 levels")
    # more records than the limit: refused by the scan, json.loads never called
    p.write_text(json.dumps([{"t": i, "x": 1} for i in range(3000)], indent=1))
    parsed = []
    real = json.loads
    monkeypatch.setattr(json, "loads", lambda *a, **k: parsed.append(1) or real(*a, **k))
    msg = _refused(p, r"t\.json:\d+: more than 2000 data records", max_rows=2000)
    assert parsed == [] and f"{p}:8002:" in msg  # the first record over the limit (4 lines each), by its line
    monkeypatch.setattr(json, "loads", real)
    p.write_text('{"data": [\n{"t": 1, "x": ' + "9" * 5000 + "}]}")
    _refused(p, r"t\.json:2: a number of more than 100 digits")
    p.write_text('{"data": [\n{"t": 1, "x": 2, "label": "' + "9" * 5000 + '"}]}')  # digits in a string: text
    assert read_table(p).column("label") == ["9" * 5000]
    p.write_text('{"data": [], "meta": {"v": [' + "1," * 4_000_000 + "1]}}")
    _refused(p, r"t\.json: a JSON table of more than 4000000 values")
    p.write_text('[{"t": 1, "x": 2, "x": 3}]')
    _refused(p, r"key 'x' repeats in an object")
    p.write_text('[{"t": 1, "A_r": 2, "a_r": 3}]')  # two columns of a table (the search tables have both)
    assert read_table(p).columns == ("t", "A_r", "a_r")
    # ... but a record reader matching names case-insensitively refuses them where both could be one role
    p.write_text('[{"t": 1, "x": 2, "X": 3}]')
    with pytest.raises(InputError, match=r"columns 'x' and 'X' could both be the x"):
        read_record(p, SPEC)
    p.write_text('[{"t": 1, "Xx": 2, "XX": 3}]')  # a mapping that matches neither exactly, both by case
    with pytest.raises(InputError, match=r"columns 'Xx' and 'XX' could both be --columns x=xx"):
        read_record(p, SPEC, columns={"x": "xx"})
    p.write_bytes(b'[{"t": 1,\n "x": "\xff"}]')
    _refused(p, r"t\.json:2: not a UTF-8 text file")


def test_a_3e6_record_json_is_refused_in_bounded_memory(tmp_path):
    """The issue's 3e6-record JSON (42 MB here, compact; it peaked at 3.4 GB for 146 MB): refused by the
    record scan before it is parsed, the process peaking well under 1 GiB (its own RSS, in a subprocess)."""
    import subprocess

    p = tmp_path / "big.json"
    p.write_text("[" + ",".join(['{"t":1,"x":2}'] * 3_000_000) + "]")
    code = (
        "import sys\n"
        "from motionsig_cli.tables import read_table, InputError\n"
        "try:\n    read_table(sys.argv[1], max_rows=1_000_000)\n"
        "except InputError as exc:\n    print(exc)\n"
        # VmHWM, this process's own peak: ru_maxrss keeps the parent's at exec (the pytest process)
        "print(next(ln.split()[1] for ln in open('/proc/self/status') if ln.startswith('VmHWM')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code, str(p)], capture_output=True, text=True, timeout=120)
    message, peak_kib = out.stdout.strip().splitlines()
    assert message.endswith("big.json:1: more than 1000000 data records (the limit for this input)"), out
    assert int(peak_kib) < 600 * 1024, f"peak RSS {int(peak_kib) / 1024:.0f} MiB"


# ------------------------------------------------------------------------------------------- cells
@pytest.mark.parametrize(
    "cell, match",
    [
        ("1_0", r"r\.csv:4: column 'x': '1_0' is not a number"),
        ("\u0661\u0662", r"r\.csv:4: column 'x': '١٢' is not a number"),  # Arabic-Indic digits
        ("\uff11\uff12", r"r\.csv:4: column 'x': '１２' is not a number"),  # full-width digits
        ("1" * 400, r"r\.csv:4: column 'x': '1111.*' is not a number"),
    ],
)
def test_only_ascii_decimal_numbers_are_numbers(tmp_path, cell, match):
    p = tmp_path / "r.csv"
    p.write_text(f"t,x,n\n0,1,1\n1,2,2\n2,{cell},3\n", encoding="utf-8")
    with pytest.raises(InputError, match=match):
        read_record(p, SPEC)
    p.write_text(f"t,x,n\n0,1,1\n1,2,2\n2,3,{cell}\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"r\.csv:4: column 'n': .* is not an integer"):
        read_record(p, SPEC)


def test_absurd_times_are_a_cell_error_without_warnings(tmp_path):
    p = tmp_path / "r.csv"
    p.write_text("t,x\n0,1\n1e300,2\n")
    with (
        np.errstate(all="raise"),
        pytest.raises(InputError, match=r"r\.csv:3: column 't': time '1e300' is beyond"),
    ):
        read_record(p, SPEC)
    p.write_text("t [ns],x\n0,1\n1.7e18,2\n")  # Unix time in nanoseconds: 1.7e9 s, accepted
    assert read_record(p, SPEC)["time"][1] == 1.7e9


def test_errors_give_their_line_and_stay_short(tmp_path):
    p = tmp_path / "r.csv"
    p.write_bytes(b"# a: 1\nt,x\n0,1\n1,\xff\n")
    _refused(p, r"r\.csv:4:3: not a UTF-8 text file \(byte 0xff\)")
    p.write_text('# units: "km"\nt,x\n0,1\n1,2\n')
    with pytest.raises(InputError, match=r"r\.csv:1: metadata 'units' must be a JSON object"):
        read_record(p, SPEC)
    p.write_text('# a: 1\n# units: {"x": "furlong"}\nt,x\n0,1\n1,2\n')
    with pytest.raises(InputError, match=r"r\.csv:2: unknown length unit 'furlong'"):
        read_record(p, SPEC)
    p.write_text("# a: " + "[" * 1000 + "\nt,x\n")
    _refused(p, r"r\.csv:1: metadata 'a': nested deeper than 64")
    p.write_text("t,y,y\n")
    _refused(p, r"r\.csv:1: duplicate column 'y'")
    p.write_text("t,X,x\n0,1,2\n")
    with pytest.raises(InputError, match=r"r\.csv:1: columns 'X' and 'x' could both be the x"):
        read_record(p, SPEC)
    p.write_text(",".join(f"c{i}" for i in range(100_000)) + "\n" + ",".join("1" * 100_000) + "\n")
    with pytest.raises(InputError, match=r"missing column 'time'.*\(99988 more\)") as exc:
        read_record(p, SPEC)
    assert len(str(exc.value)) < 600
    assert len(str(InputError("x" * 10**6))) <= MAX_MESSAGE_CHARS


# -------------------------------------------------------------------------------------------- fuzz
GOOD = '# command: "simulate"\n# units: {"x": "km"}\nt,x,n,label\n0,1.5,1,a\n0.5,2,2,b\n1,,3,c\n'
HOSTILE = [
    "\0", "\xff", "\ufeff", "\r", "\n", ",", '"', "#", ":", "{", "[", "]", "}", "1_0", "\u0661", "\uff11",
    "1e300", "-1e309", "nan", "inf", "9" * 5000, "[" * 3000, "{\"a\":" * 100, '{"a":1,"a":2}', "T", "X", "t,T", "x,X", "é",
    '# codes: "file:/dev/zero"', "# units: {\"x\": 5}", "null", "true", "2026-05-01T12:00:00Z", "-", "\t",
]  # fmt: skip


def _read_all(path) -> None:
    """Every core reader on ``path``: a table, a record, numbers of its columns."""
    try:
        t = read_table(path, max_rows=50)
    except InputError:
        return
    for c in t.columns[:4]:
        for integer in (False, True):
            with contextlib.suppress(InputError):
                t.numeric(c, integer=integer)
    with contextlib.suppress(InputError):
        read_record(t, SPEC)
    with contextlib.suppress(InputError):
        read_record(path, SPEC)


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(
    cuts=st.lists(st.tuples(st.integers(0, len(GOOD)), st.sampled_from(HOSTILE)), max_size=6),
    as_json=st.booleans(),
    raw=st.binary(max_size=64),
)
def test_fuzz_every_case_is_a_result_or_one_input_error(tmp_path_factory, cuts, as_json, raw):
    """A valid record (CSV, or the same as JSON) with hostile pieces spliced in, and random bytes: each
    read ends in a result or an :class:`InputError` (never another exception, a hang or a warning) and
    allocates at most 64 MiB."""
    text = GOOD
    if as_json:
        text = json.dumps(
            {
                "meta": {"units": {"x": "km"}},
                "data": [{"t": 0, "x": 1.5, "n": 1}, {"t": 0.5, "x": 2, "n": 2}],
            },
            indent=1,
        )
    for at, piece in sorted(cuts, reverse=True):
        at = min(at, len(text))
        text = text[:at] + piece + text[at:]
    d = tmp_path_factory.mktemp("fuzz")
    for name, data in (
        ("f.csv", text.encode("utf-8", "surrogatepass")),
        ("b.csv", raw),
        ("c.csv", raw + GOOD.encode()),
    ):
        (d / name).write_bytes(data)
        with _deadline(), _peak(64), np.errstate(all="raise"):
            _read_all(d / name)
