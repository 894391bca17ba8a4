"""Issue 39, the fuzz of every command-line reading path over a fixed corpus of hostile files: an empty file,
binary garbage, a directory, a FIFO without a writer, ``/dev/zero``, a symbolic link loop, JSON nested
100,000 deep, a 5,000-digit integer, Arabic-Indic and full-width digits, ``1_0`` and two columns that differ
only in case. Each must end with exit code 2 and exactly one line on stderr naming the file (``<stdin>`` for
``-``), no traceback, and no output file; a FIFO must not hang and ``/dev/zero`` must end under a 1 GiB
memory cap.

The commands run in-process (the FIFO cases with a guard thread that plays the writer when a command opens
the FIFO, so an old reader that blocks is released and the case fails instead of hanging); ``/dev/zero``
runs every path in one subprocess under ``RLIMIT_AS``. The command layer refuses special files by name
before any read (:func:`motionsig_cli.cli.common.refuse_special_inputs`); the content cases rest on the
core readers (JSON limits, ASCII numbers, case twins).
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from motionsig_cli.cli.app import main

AIRCRAFT = ("--aircraft", "48.3538,11.7861,3.45")
TRACK = ("--clock", "track")  # the example's TOA record has an outage epoch with three receivers

# name → (argv with {f} for the hostile file and {base} for the base files' directory, the base file the
# content cases corrupt)
PATHS: dict[str, tuple[tuple[str, ...], str]] = {
    "detect": (("detect", "{f}"), "rec.csv"),
    "detect-stdin": (("detect", "-"), "rec.csv"),
    "maneuver": (("maneuver", "{f}", "--method", "glr"), "meas.csv"),
    "maneuver-stdin": (("maneuver", "-", "--method", "glr"), "meas.csv"),
    "slrt": (("slrt", "{f}", "--sensor-table", "{base}/sen.csv"), "det.csv"),
    "slrt-sensor-table": (("slrt", "{base}/det.csv", "--sensor-table", "{f}"), "sen.csv"),
    "solve": (("track-sat", "solve", "{f}", "--receivers", "{base}/stations.csv", *TRACK), "toa.csv"),
    "solve-receivers": (
        ("track-sat", "solve", "{base}/toa.csv", "--receivers", "{f}", *TRACK),
        "stations.csv",
    ),
    "constellation-receivers": (
        ("track-sat", "constellation", "--receivers", "{f}", *AIRCRAFT),
        "stations.csv",
    ),
    "constellation-sats": (("track-sat", "constellation", "--sats", "{f}"), "sats.csv"),
    "simulate-codes": (("simulate", "--codes", "{f}"), "codes.csv"),
    "encode-correlations": (("encode", "correlations", "{f}"), "codes.csv"),
    "encode-correlations-stdin": (("encode", "correlations", "-"), "codes.csv"),
    "mac-roc-code": (
        ("mac-roc", "bounds", "--density", "psk", "--theta", "0.5", "--code", "file:{f}"),
        "codes.csv",
    ),
}
FILE_PATHS = [name for name in PATHS if not name.endswith("-stdin")]


# the column of each base file that its reader reads as numbers (a corrupted column nobody reads is no test)
TARGET = {"rec.csv": "y", "meas.csv": "z_x", "det.csv": "range [m]", "sen.csv": "x [m]", "toa.csv": "toa",
          "stations.csv": "latitude", "sats.csv": "latitude_deg", "codes.csv": "value"}  # fmt: skip


def _cell(text: str, base: str, value: str) -> str:
    """The base CSV with its :data:`TARGET` cell of the first data row replaced by ``value``."""
    lines = text.splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    j = lines[header].split(",").index(TARGET[base])
    cells = lines[header + 1].split(",")
    cells[j] = value
    lines[header + 1] = ",".join(cells)
    return "\n".join(lines) + "\n"


def _case_twin(text: str, base: str) -> str:
    """The base CSV with a copy of its :data:`TARGET` column under the same name in upper case (``y``, ``Y``)."""
    lines = text.splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    j = lines[header].split(",").index(TARGET[base])
    out = lines[:header]
    for i, line in enumerate(lines[header:]):
        cell = line.split(",")[j]
        out.append(f"{line},{cell.upper() if i == 0 else cell}")
    return "\n".join(out) + "\n"


CONTENT: dict[str, object] = {
    "empty": b"",
    "garbage": bytes(range(256)) * 8 + b"\x00" * 512,
    "deep-json": b"[" * 100_000 + b"]" * 100_000,
    "huge-int": lambda t, b: _cell(t, b, "1" + "0" * 4999),
    "arabic-digits": lambda t, b: _cell(t, b, "\u0661\u0662"),
    "fullwidth-digits": lambda t, b: _cell(t, b, "\uff11\uff12"),
    "underscore": lambda t, b: _cell(t, b, "1_0"),
    "case-duplicate-columns": _case_twin,
}
SPECIAL = ["directory", "symlink-loop", "fifo"]

# Readers that look columns up by their exact name keep a column that differs in letter case only (the table
# format's rule since main e2690ec: refused only where one role could match both); for them the case twin is
# not an error, and the run must use the exact column (and succeed).
EXACT_NAMES = {"detect", "detect-stdin", "constellation-sats", "simulate-codes", "encode-correlations",
               "encode-correlations-stdin", "mac-roc-code"}  # fmt: skip


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> Path:
    """Valid inputs of every reading path, written by the commands themselves."""
    from tests.cli.test_track_sat_solve_cli import write_example

    d = tmp_path_factory.mktemp("base")
    runs = [
        ("simulate", "-o", "rec.csv"),
        ("maneuver", "--view", "measurements", "--runs", "1", "--sigma", "100", "-o", "meas.csv"),
        ("slrt", "--view", "detections", "--runs", "1", "--scans", "3", "-o", "det.csv"),
        ("slrt", "--view", "sensors", "-o", "sen.csv"),
        ("track-sat", "constellation", "--view", "satellites", "-o", "sats.csv"),
        ("encode", "gold", "-o", "codes.csv"),
    ]
    for args in runs:
        assert main([*args[:-1], str(d / args[-1]), "-q"]) == 0, args
    write_example(d)
    return d


def _argv(name: str, f: str, base: Path, out: Path) -> list[str]:
    args, _ = PATHS[name]
    return [a.replace("{f}", f).replace("{base}", str(base)) for a in args] + ["-o", str(out)]


def _check(rc: int, out: str, err: str, names: str, target: Path) -> None:
    """The promise: exit 2, one line naming the file, no traceback, nothing on stdout, no output file."""
    assert rc == 2, (rc, err[-500:])
    assert out == "", out[:200]
    assert err.count("\n") == 1 and "Traceback" not in err, err[-2000:]
    assert names in err, err
    assert len(err) < 2000, f"{len(err)} characters"
    assert not target.exists()


def _params(names: list[str], cases: list[str]) -> list[object]:
    return [pytest.param(n, c, id=f"{n}-{c}") for n in names for c in cases]


@pytest.mark.parametrize(("name", "case"), _params(list(PATHS), list(CONTENT)))
def test_hostile_content_is_one_line_exit_2(capsys, monkeypatch, tmp_path, base, name, case):
    make = CONTENT[case]
    file = PATHS[name][1]
    raw = make if isinstance(make, bytes) else make((base / file).read_text(), file)  # type: ignore[operator]
    data = raw.encode() if isinstance(raw, str) else raw
    out = tmp_path / "out.csv"
    if name.endswith("-stdin"):
        monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data), encoding="utf-8"))
        f, names = "-", "<stdin>"
    else:
        path = tmp_path / ("hostile.json" if case == "deep-json" else "hostile.csv")
        path.write_bytes(data)
        f, names = str(path), path.name
    rc = main(_argv(name, f, base, out))
    stdout, err = capsys.readouterr()
    if case == "case-duplicate-columns" and name in EXACT_NAMES:
        assert rc == 0 and out.exists(), err
        return
    _check(rc, stdout, err, names, out)


class _Writer(threading.Thread):
    """Plays the writer of a FIFO as soon as a process opens it for reading (then closes it: EOF), so a
    command that opens a FIFO ends instead of hanging; ``opened`` says whether one did."""

    def __init__(self, fifo: Path) -> None:
        super().__init__(daemon=True)
        self.fifo, self.opened, self.done = fifo, False, threading.Event()

    def run(self) -> None:
        deadline = time.monotonic() + 30
        while not self.done.is_set() and time.monotonic() < deadline:
            try:
                fd = os.open(self.fifo, os.O_WRONLY | os.O_NONBLOCK)
            except OSError:  # ENXIO: no reader yet
                time.sleep(0.005)
                continue
            self.opened = True
            os.close(fd)
            return


@pytest.mark.parametrize(("name", "case"), _params(FILE_PATHS, SPECIAL))
def test_special_files_are_refused_by_name_without_hanging(capsys, tmp_path, base, name, case):
    out = tmp_path / "out.csv"
    if case == "directory":
        path = tmp_path / "adir"
        path.mkdir()
    elif case == "symlink-loop":
        path = tmp_path / "loop.csv"
        path.symlink_to(path)
    else:
        path = tmp_path / "fifo.csv"
        os.mkfifo(path)
    writer = _Writer(path) if case == "fifo" else None
    if writer:
        writer.start()
    try:
        rc = main(_argv(name, str(path), base, out))
    finally:
        if writer:
            writer.done.set()
            writer.join()
    stdout, err = capsys.readouterr()
    assert not (writer and writer.opened), f"the command opened the FIFO (it would hang): {err[-300:]}"
    _check(rc, stdout, err, path.name, out)


_DEV_ZERO_SCRIPT = """
import json, resource, sys
resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))
from motionsig_cli.cli.app import main
results = {}
for name, argv in json.loads(sys.argv[1]).items():
    import contextlib, io
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            rc = main(argv)
        except BaseException as exc:
            rc = repr(exc)
    results[name] = [rc, err.getvalue()]
print(json.dumps(results))
"""


@pytest.fixture(scope="module")
def dev_zero(base, tmp_path_factory) -> dict[str, tuple[object, str, Path]]:
    """Every reading path on /dev/zero, in one subprocess under a 1 GiB address-space cap."""
    tmp = tmp_path_factory.mktemp("zero")
    argv = {name: _argv(name, "/dev/zero", base, tmp / f"{name}.csv") for name in FILE_PATHS}
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    proc = subprocess.run(
        [sys.executable, "-c", _DEV_ZERO_SCRIPT, json.dumps(argv)],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    results = json.loads(proc.stdout.strip().splitlines()[-1])
    return {name: (rc, err, tmp / f"{name}.csv") for name, (rc, err) in results.items()}


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
@pytest.mark.parametrize(("name", "case"), _params(FILE_PATHS, ["dev-zero"]))
def test_dev_zero_is_one_line_under_a_memory_cap(dev_zero, name, case):
    rc, err, out = dev_zero[name]
    _check(rc, "", err, "/dev/zero", out)  # type: ignore[arg-type]
