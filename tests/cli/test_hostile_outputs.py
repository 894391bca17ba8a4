"""Issue 39, output targets: before any work, every command refuses by name (one line, exit 2) an output
that is one of its input files — by the same name, through ``..``, a symbolic link or a hard link — an
unwritable target, a symbolic link loop and a FIFO that no process reads; a full device fails the write in
one line. Nothing is written, nothing half-written, no traceback (``--debug`` shows one)."""

import contextlib
import os
import threading
from pathlib import Path

import pytest

from motionsig_cli.cli.app import main
from tests.cli.helpers import one_line_error, run

# (command line with {in} for the input file, the option that reads it): each reads the file it names
READERS = [
    (("detect", "{in}"), "input record"),
    (("detect", "-", "--codes", "{in}"), "--codes"),
    (("detect", "-", "--codes", "file:{in}"), "--codes"),
    (("simulate", "--codes", "{in}"), "--codes"),
    (("encode", "correlations", "{in}"), "input record"),
    (("maneuver", "{in}"), "input record"),
    (("maneuver", "--input", "{in}"), "--input"),
    (("slrt", "{in}", "--sensor-table", "{other}"), "input record"),
    (("slrt", "{other}", "--sensor-table", "{in}"), "--sensor-table"),
    (("track-sat", "solve", "{in}", "--receivers", "{other}"), "measurement record"),
    (("track-sat", "solve", "{other}", "--receivers", "{in}"), "--receivers"),
    (("track-sat", "constellation", "--receivers", "{in}"), "--receivers"),
    (("track-sat", "constellation", "--sats", "{in}"), "--sats"),
    (("mac-roc", "bounds", "--density", "psk", "--code", "file:{in}"), "--code"),
    (("mac-roc", "bandwidth", "--code", "barker13;file:{in}"), "--code"),
    (("encode", "ebpsk", "--code", "file:{in}"), "--code"),
]
CONTENT = "precious,data\n1,2\n"


def _alias(tmp_path: Path, how: str) -> str:
    """Another name of tmp_path/in.csv."""
    if how == "same":
        return str(tmp_path / "in.csv")
    if how == "dotdot":
        (tmp_path / "sub").mkdir()
        return str(tmp_path / "sub" / ".." / "in.csv")
    if how == "symlink":
        (tmp_path / "link.csv").symlink_to(tmp_path / "in.csv")
        return str(tmp_path / "link.csv")
    os.link(tmp_path / "in.csv", tmp_path / "hard.csv")
    return str(tmp_path / "hard.csv")


@pytest.mark.parametrize(("args", "what"), READERS, ids=lambda v: " ".join(v) if isinstance(v, tuple) else v)
@pytest.mark.parametrize("how", ["same", "dotdot", "symlink", "hardlink"])
def test_an_output_that_is_an_input_file_is_refused_before_any_work(capsys, tmp_path, args, what, how):
    src = tmp_path / "in.csv"
    src.write_text(CONTENT)
    (tmp_path / "other.csv").write_text("x\n")
    target = _alias(tmp_path, how)
    argv = [a.replace("{in}", str(src)).replace("{other}", str(tmp_path / "other.csv")) for a in args]
    err = one_line_error(capsys, *argv, "-o", target)
    assert "--out" in err and what in err and "in.csv" in err, err
    assert src.read_text() == CONTENT


@pytest.mark.parametrize("option", ["--plot", "--plot-compare"])
def test_a_figure_that_is_the_input_is_refused(capsys, tmp_path, option):
    src = tmp_path / "in.png"
    src.write_text(CONTENT)
    err = one_line_error(capsys, "maneuver", str(src), option, str(src))
    assert option in err and "input record" in err
    assert src.read_text() == CONTENT


def _release(fifo: Path, done: threading.Event) -> None:
    """Unless ``done`` is set within 3 s, open ``fifo`` for reading and drain it."""
    if done.wait(3):
        return
    fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        while not done.wait(0.01):
            with contextlib.suppress(BlockingIOError):
                os.read(fd, 1 << 16)
    finally:
        os.close(fd)


def _listing(tmp_path: Path) -> list[str]:
    return sorted(p.name for p in tmp_path.iterdir())


@pytest.mark.parametrize(
    ("target", "needle"),
    [
        ("/sys/motionsig-out.csv", "cannot write in directory '/sys'"),
        ("/proc/motionsig-out.csv", "cannot write in directory '/proc'"),
        ("{tmp}", "is a directory"),
        ("{tmp}/no/such/dir/o.csv", "does not exist"),
        ("{tmp}/loop", "symbolic link loop"),
        ("{tmp}/fifo", "a FIFO that no process reads"),
    ],
)
def test_unwritable_output_targets_are_one_line(capsys, tmp_path, target, needle):
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    os.mkfifo(tmp_path / "fifo")
    before = _listing(tmp_path)
    done = threading.Event()
    guard = threading.Thread(target=_release, args=(tmp_path / "fifo", done), daemon=True)
    guard.start()  # a command that blocks opening the FIFO for writing is released (and fails), not hung
    try:
        err = one_line_error(capsys, "encode", "gold", "-o", target.replace("{tmp}", str(tmp_path)))
    finally:
        done.set()
        guard.join()
    assert needle in err, err
    assert _listing(tmp_path) == before  # no temporary file left behind


def test_unwritable_figure_target_is_refused_before_any_work(capsys, tmp_path):
    err = one_line_error(capsys, "jam-bound", "curves", "-o", str(tmp_path / "o.csv"), "--plot", "/sys/p.png")
    assert "--plot" in err and "/sys" in err
    assert _listing(tmp_path) == []


def test_a_symlink_loop_as_output_through_a_directory_is_refused(capsys, tmp_path):
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    err = one_line_error(capsys, "encode", "gold", "-o", str(tmp_path / "a" / "o.csv"))
    assert "--out" in err


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_a_full_device_is_one_line(capsys):
    err = one_line_error(capsys, "encode", "gold", "-o", "/dev/full")
    assert "/dev/full" in err and "No space left on device" in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes in a read-only directory")
def test_a_read_only_directory_is_refused(capsys, tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        err = one_line_error(capsys, "encode", "gold", "-o", str(ro / "o.csv"))
    finally:
        ro.chmod(0o700)
    assert "cannot write in directory" in err and list(ro.iterdir()) == []


def test_debug_shows_the_traceback(tmp_path):
    with pytest.raises(Exception, match=r"No space left|cannot write"):
        main(["encode", "gold", "-o", "/dev/full", "--debug"])


def test_an_output_fifo_with_a_reader_is_written(capsys, tmp_path):
    """A FIFO that a process reads (``-o >(gzip > x.gz)``) is still a valid target."""
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        rc, _, err = run(capsys, "encode", "gold", "-o", str(fifo))
        data = os.read(fd, 1 << 16)
    finally:
        os.close(fd)
    assert rc == 0, err
    assert data.startswith(b"# command:")
