"""Issue 39, silent nonsense in ``slrt FILE --sensor-table``: a period in the metadata that contradicts the
rows' times, and times that go backwards, repeat, jump a century or equal 1e300, are refused in one line
naming the file, the line and the column (and, for a contradiction, both values) — they used to change the
scores silently."""

import re

import pytest

from tests.cli.helpers import one_line_error, run


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A simulated run's detections (scan and time columns, metadata T: 1.0) and its sensors table."""
    from motionsig_cli.cli.app import main

    tmp = tmp_path_factory.mktemp("slrt")
    d, s = tmp / "d.csv", tmp / "s.csv"
    assert main(["slrt", "--view", "detections", "--runs", "1", "--scans", "4", "--clutter", "0.2", "-o", str(d),
                 "-q"]) == 0  # fmt: skip
    assert main(["slrt", "--view", "sensors", "-o", str(s), "-q"]) == 0
    return d.read_text(), s


def _edit(text: str, *, meta_T: str | None = None, scan: int | None = None, time: str = "",
          drop_scan: bool = False) -> str:  # fmt: skip
    """The detections with metadata T replaced, the time of every row of ``scan`` set to ``time``, and
    with ``drop_scan`` the scan column removed (a time-only record)."""
    out = []
    for line in text.splitlines():
        if line.startswith("# T:") and meta_T is not None:
            line = f"# T: {meta_T}"
        elif not line.startswith("#"):
            cells = line.split(",")
            if scan is not None and cells[0] == str(scan):
                cells[1] = time
            line = ",".join(cells[1:] if drop_scan else cells)
        out.append(line)
    return "\n".join(out) + "\n"


CASES = [
    (dict(meta_T="1e-300"), r":15: column 'time': .*T = 1e-300 s \(the file's metadata 'T'\).*period of 1 s"),
    (dict(scan=3, time="0.5"), r":\d+: column 'time': time goes backwards: 0.5 s at scan 3, after 2 s"),
    (dict(scan=3, time="2.0"), r":\d+: column 'time': time repeats: 2 s at scan 3"),
    (
        dict(scan=4, time="3155760004.0"),
        r":\d+: column 'time': time 3.15576e\+09 s at scan 4 is .* periods off",
    ),
    (dict(scan=4, time="1e300"), r":\d+: column 'time': time '?1e\+?300'? (s is not a time|is beyond)"),
    (dict(meta_T="1e-300", drop_scan=True), r":\d+: column 'time': the period T = 1e-300 s .*1 s apart"),
    (
        dict(scan=4, time="1e300", drop_scan=True),
        r":\d+: column 'time': time '?1e\+?300'? (s is not a time|is beyond)",
    ),
    (dict(meta_T="2", drop_scan=True), r":\d+: column 'time': the period T = 2 s .* 1 s after"),
]


@pytest.mark.parametrize(("edit", "pattern"), CASES)
def test_times_that_contradict_the_period_or_themselves_are_refused(capsys, tmp_path, files, edit, pattern):
    text, sensors = files
    d = tmp_path / "bad.csv"
    d.write_text(_edit(text, **edit))
    out = tmp_path / "o.csv"
    err = one_line_error(capsys, "slrt", str(d), "--sensor-table", str(sensors), "-o", str(out))
    assert re.search(re.escape(str(d)) + pattern, err), err
    assert "RuntimeWarning" not in err and not out.exists()


@pytest.mark.parametrize("drop_scan", [False, True])
def test_the_consistent_record_is_still_read(capsys, tmp_path, files, drop_scan):
    text, sensors = files
    d = tmp_path / "ok.csv"
    d.write_text(_edit(text, drop_scan=drop_scan))
    rc, out, err = run(capsys, "slrt", str(d), "--sensor-table", str(sensors), "-q")
    assert rc == 0, err
    assert "confirmed" in out


def test_a_given_T_that_contradicts_the_times_names_the_option(capsys, files, tmp_path):
    text, sensors = files
    d = tmp_path / "d.csv"
    d.write_text(text)
    err = one_line_error(capsys, "slrt", str(d), "--sensor-table", str(sensors), "--T", "1e-3")
    assert "T = 0.001 s (--T)" in err and "period of 1 s" in err
