"""Table format: CSV with provenance lines, JSON, reader errors."""

import json

import numpy as np
import pytest

from motionsig_cli.tables import InputError, Table, format_csv, format_json, make_meta, read_table


def _table():
    meta = make_meta("encode test", R=1e-5, name="x", flag=True, lst=[1, 2], none=None, arr=np.float64(0.1))
    rows = [(0, 0.1 + 0.2, "a,b", True), (1, -1e-300, "c", False)]
    return Table(columns=("i", "x", "s", "b"), rows=rows, meta=meta)


def test_csv_round_trip_with_meta(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text(format_csv(_table()))
    back = read_table(path)
    assert back.meta["R"] == 1e-5 and back.meta["name"] == "x" and back.meta["flag"] is True
    assert back.meta["lst"] == [1, 2] and back.meta["none"] is None and back.meta["arr"] == 0.1
    assert back.meta["command"] == "encode test" and "motionsig_version" in back.meta
    assert back.columns == ("i", "x", "s", "b")
    x = back.numeric("x")
    assert x[0] == 0.1 + 0.2 and x[1] == -1e-300  # full precision round trip
    assert back.column("s") == ["a,b", "c"]
    n_meta = len(_table().meta)  # one "# key: value" line each, then the header
    assert back.lines == (n_meta + 2, n_meta + 3)


def test_comment_lines_then_plain_csv(tmp_path):
    """Everything after the '#' block is plain CSV: the csv module reads it knowing nothing of the meta."""
    import csv

    text = format_csv(_table())
    rows = list(csv.reader(ln for ln in text.splitlines() if not ln.startswith("#")))
    assert rows[0] == ["i", "x", "s", "b"] and rows[1] == ["0", repr(0.1 + 0.2), "a,b", "true"]


def test_json():
    doc = json.loads(format_json(_table()))
    assert doc["columns"] == ["i", "x", "s", "b"]
    assert doc["data"][0]["s"] == "a,b" and doc["meta"]["R"] == 1e-5


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", "no header"),
        ("# a: 1\n", "no header"),
        ("a,b\n1,2\n3\n", r"t.csv:3: expected 2 fields, found 1"),
        ("a,a\n1,2\n", "duplicate"),
    ],
)
def test_reader_errors_name_file_and_line(tmp_path, text, match):
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=match):
        read_table(path)


def test_numeric_error_names_line(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("# k: 1\nchip,value\n0,1\n1,abc\n")
    t = read_table(path)
    with pytest.raises(InputError, match=r"t.csv:4: column 'value': 'abc' is not a number"):
        t.numeric("value")
    with pytest.raises(InputError, match="missing column 'code'"):
        t.column("code")


def test_missing_file():
    with pytest.raises(InputError, match="cannot read"):
        read_table("/nonexistent/x.csv")
