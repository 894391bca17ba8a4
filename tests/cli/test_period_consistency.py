"""Issue 39, the period-versus-times rule of ``maneuver FILE`` and ``track-sat solve``: a stated period (the
metadata ``T``; the epoch numbers of a TOA record) that contradicts the times, and absurd times (1e300, a
century late), are refused in one line naming the file, the line, the column and both values; no
RuntimeWarning reaches the screen."""

import re

import pytest

from tests.cli.helpers import one_line_error


@pytest.fixture(scope="module")
def measurements(tmp_path_factory) -> str:
    """A maneuver measurements record (metadata T: 1.0, times 1 s apart)."""
    from motionsig_cli.cli.app import main

    path = tmp_path_factory.mktemp("man") / "m.csv"
    assert main(["maneuver", "--view", "measurements", "--runs", "1", "--sigma", "100", "-o", str(path)]) == 0
    return path.read_text()


def _time(text: str, row: int, value: str) -> str:
    """The record with the time of data row ``row`` (-1: the last) replaced."""
    lines = text.splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    col = lines[header].split(",").index("t")
    i = len(lines) - 1 if row < 0 else header + row
    cells = lines[i].split(",")
    cells[col] = value
    lines[i] = ",".join(cells)
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    ("edit", "pattern"),
    [
        (lambda t: t.replace("# T: 1.0", "# T: 2.0"), r": metadata 'T' = 2 s disagrees with the period of the record's "
                                                       r"times, 1 s"),
        (lambda t: _time(t, 5, "0.5"), r":\d+: column 'scan': scan \d+ is earlier than the scan of an earlier time"),
        (lambda t: _time(t, -1, "3155760004"), r":\d+: column 'scan': .* its time is 3155760004 periods of 1 s"),
        (lambda t: _time(t, -1, "1e300"), r":\d+: column 't': time '?1e\+?300'? (s is not a time|is beyond)"),
    ],
    ids=["T", "backwards", "century", "1e300"],
)  # fmt: skip
def test_maneuver_times_that_contradict_the_period_are_refused(capsys, tmp_path, measurements, edit, pattern):
    f = tmp_path / "m.csv"
    f.write_text(edit(measurements))
    err = one_line_error(capsys, "maneuver", str(f), "--method", "glr", "-o", str(tmp_path / "o.csv"))
    assert re.search(re.escape(str(f)) + pattern, err), err
    assert not (tmp_path / "o.csv").exists()


def test_maneuver_a_repeated_time_is_a_conflict_kept_first_or_refused_when_strict(capsys, tmp_path, measurements):
    """Two rows at one time with other positions: by default the first is kept and the metadata counts the
    other; with --strict the record is refused naming the line."""
    f = tmp_path / "m.csv"
    f.write_text(_time(measurements, 5, "3"))
    err = one_line_error(capsys, "maneuver", str(f), "--method", "glr", "--strict", "-o", str(tmp_path / "o.csv"))
    assert re.search(re.escape(str(f)) + r":\d+: column 't': the row has another position at the time", err), err
    assert not (tmp_path / "o.csv").exists()
    from motionsig_cli.cli.app import app  # noqa: F401  (the command runs in-process below)
    from motionsig_cli.maneuver.record import read_track_record

    assert read_track_record(f).hygiene["conflicting_duplicates"] == 1


@pytest.fixture(scope="module")
def toa(tmp_path_factory):
    from tests.cli.test_track_sat_solve_cli import write_example

    tmp = tmp_path_factory.mktemp("toa")
    write_example(tmp)
    return (tmp / "toa.csv").read_text(), tmp / "stations.csv"


def _shift_epoch(text: str, epoch: int, by: float, *, toa: bool = True) -> str:
    lines = text.splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        if cells[0] == str(epoch):
            cells[1] = repr(float(cells[1]) + by)
            if toa:
                cells[3] = repr(float(cells[3]) + by)
        out.append(",".join(cells))
    return "\n".join(out) + "\n"


@pytest.mark.parametrize(
    ("by", "clock", "pattern"),
    [
        (
            3155760000.0,
            "track",
            r":\d+: column 'time': epoch 119 at .* off the grid .*period 1 s.* contradict",
        ),
        (2.5, "track", r":\d+: column 'time': epoch 119 at .* off the grid"),
        (1e300, "snapshot", r":\d+: column 'time': time '?1e\+?300'? (s is|is beyond)"),
    ],
)
def test_track_sat_solve_refuses_epoch_numbers_that_contradict_the_times(
    capsys, tmp_path, toa, by, clock, pattern
):
    text, stations = toa
    f = tmp_path / "toa.csv"
    f.write_text(_shift_epoch(text, 119, by, toa=by < 1e12))
    out = tmp_path / "o.csv"
    err = one_line_error(capsys, "track-sat", "solve", str(f), "--receivers", str(stations), "--clock", clock,
                         "-o", str(out))  # fmt: skip
    assert re.search(re.escape(str(f)) + pattern, err), err
    assert not out.exists()
