"""The user-record reader: roles, --columns, units, ISO 8601 times, missing values, limits, JSON input.

Every record here is written by the test itself (text, the csv module, json), not by motionsig.
"""

import csv
import io
import json
import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError
from motionsig_cli.records import (
    Record,
    RecordSpec,
    Role,
    parse_columns,
    parse_units,
    read_record,
    uniform_grid,
)

SPEC = RecordSpec(
    (
        Role("time", ("t", "timestamp"), kind="time", order="increasing"),
        Role("x", ("east",), quantity="length", missing=True),
        Role("y", ("north",), quantity="length", missing=True),
        Role("bearing", (), quantity="angle", required=False),
        Role("sensor", (), kind="label", required=False),
    ),
    max_rows=100,
)


def _write(tmp_path, text, name="r.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_aliases_units_and_missing(tmp_path):
    p = _write(tmp_path, '# units: {"north": "km"}\nTime,East [ft],north\n0,1,2\n1,,3\n2,NaN,4\n')
    rec = read_record(p, SPEC)
    assert rec.columns == {"time": "Time", "x": "East [ft]", "y": "north"}
    assert rec.units == {"time": "s", "x": "ft", "y": "km"}
    np.testing.assert_array_equal(rec["time"], [0.0, 1.0, 2.0])
    assert rec["x"][0] == 0.3048 and math.isnan(rec["x"][1]) and math.isnan(rec["x"][2])
    np.testing.assert_array_equal(rec["y"], [2000.0, 3000.0, 4000.0])
    assert rec.lines.tolist() == [3, 4, 5] and not rec.has("bearing")


def test_columns_option_and_units_option(tmp_path):
    p = _write(tmp_path, "stamp,e,n,b\n0,1,2,90\n1,2,3,180\n")
    rec = read_record(p, SPEC, columns="time=stamp,x=e,y=n,bearing=b", units="bearing=deg,time=ms")
    assert rec["bearing"].tolist() == [math.pi / 2, math.pi]
    assert rec["time"].tolist() == [0.0, 1e-3]
    assert rec.provenance()["input_columns"]["x"] == "e"


def test_iso_timestamps_relative_to_first(tmp_path):
    p = _write(
        tmp_path,
        "timestamp,x,y\n2026-05-01T12:00:00Z,0,0\n2026-05-01T12:00:00.250Z,0,0\n"
        "2026-05-01T12:00:02.000001+00:00,0,0\n",
    )
    rec = read_record(p, SPEC)
    assert rec["time"].tolist() == [0.0, 0.25, 2.000001]
    assert rec.time_origin == "2026-05-01T12:00:00+00:00"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("t,x,y\n0,1,2\n0,1,2\n", r"r.csv:3: column 't': time repeats"),
        ("t,x,y\n1,1,2\n0,1,2\n", r"r.csv:3: column 't': time goes backwards"),
        ("t,x,y\n0,abc,2\n", r"r.csv:2: column 'x': 'abc' is not a number"),
        ("t,x,y\n0,inf,2\n", r"r.csv:2: column 'x': 'inf' is not finite"),
        ("t,x\n0,1\n", r"r.csv:1: missing column 'y'"),
        ("t,x [furlong],y\n0,1,2\n", r"r.csv:1: column 'x \[furlong\]': unknown length unit 'furlong'"),
        ("t,time,x,y\n0,0,1,2\n", r"could both be the time"),
        ("t,x,y\n2026-05-01T12:00:00,1,2\n2026-05-01T12:00:01Z,1,2\n", r"r.csv:3: .*time zone"),
        ("t,x,y\n2026-05-01T12:00:00,1,2\nyesterday,1,2\n", r"r.csv:3: column 't': 'yesterday' is neither"),
        ("t,x,y\n0,1,2\n1,1,2\n", None),
        ("", "no header"),
        ("t,x,y,sensor\n0,1,2,\n", r"r.csv:2: column 'sensor': missing value"),
    ],
)
def test_bad_records_name_file_line_column(tmp_path, text, match):
    p = _write(tmp_path, text)
    if match is None:
        assert len(read_record(p, SPEC)) == 2
    else:
        with pytest.raises(InputError, match=match):
            read_record(p, SPEC)


def test_row_limit_is_checked_while_reading(tmp_path):
    rows = "".join(f"{i},0,0\n" for i in range(101))
    p = _write(tmp_path, "t,x,y\n" + rows)
    with pytest.raises(InputError, match=r"r.csv:102: more than 100 data rows"):
        read_record(p, SPEC)


@pytest.mark.parametrize(
    ("text", "field", "match"),
    [
        ("time", "columns", "role=column"),
        ("x=a,x=b", "columns", "twice"),
        ("z=a", "columns", "not a column"),
        ("x=a,y=a", "columns", "two roles"),
    ],
)
def test_columns_option_errors(text, field, match):
    with pytest.raises(ConfigError, match=match) as exc:
        parse_columns(text, SPEC)
    assert exc.value.field == field


@pytest.mark.parametrize(
    ("text", "match"), [("x=furlong", "not a length unit"), ("sensor=m", "no unit"), ("bearing", "role=unit")]
)
def test_units_option_errors(text, match):
    with pytest.raises(ConfigError, match=match):
        parse_units(text, SPEC)


def test_json_records_and_their_lines(tmp_path):
    doc = {
        "meta": {"T": 1.0},
        "columns": ["t", "x", "y"],
        "data": [{"t": 0, "x": 1.5, "y": None}, {"t": 1, "x": "oops", "y": 2}],
    }
    p = _write(tmp_path, json.dumps(doc, indent=1), "r.json")
    with pytest.raises(InputError, match=r"r.json:(\d+): column 'x': 'oops' is not a number") as exc:
        read_record(p, SPEC)
    line = int(str(exc.value).split(":")[1])
    assert json.dumps(doc, indent=1).splitlines()[line - 1].strip() == "{"  # the record's opening line
    doc["data"][1]["x"] = 2
    p.write_text(json.dumps(doc, indent=1))
    rec = read_record(p, SPEC)
    assert rec.meta == {"T": 1.0} and math.isnan(rec["y"][0]) and rec["x"].tolist() == [1.5, 2.0]


def test_csv_written_by_the_csv_module(tmp_path):
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["timestamp", "east", "north", "sensor"])
    w.writerow(["2026-01-01 00:00:00", 1.0, 2.0, "radar A"])
    w.writerow(["2026-01-01 00:00:01.5", 3.0, 4.0, "radar, B"])
    rec = read_record(_write(tmp_path, buf.getvalue()), SPEC)
    assert rec["sensor"].tolist() == ["radar A", "radar, B"] and rec["time"].tolist() == [0.0, 1.5]


def test_uniform_grid_with_gaps_and_jitter():
    rng = np.random.default_rng(1)
    k_true = np.array([0, 1, 2, 4, 5, 9, 10])
    times = 100.0 + 0.5 * k_true + rng.uniform(-1e-4, 1e-4, k_true.size)
    rec = Record({}, np.arange(2, 9), {"time": "t"}, {}, None, (), {}, "r.csv")
    k, T = uniform_grid(rec, times)
    assert k.tolist() == k_true.tolist() and abs(T - 0.5) < 1e-4
    times[3] += 0.1  # 0.2 periods off
    with pytest.raises(InputError, match=r"r.csv:5: column 't': .*non-uniform"):
        uniform_grid(rec, times)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"kind": "blob"}, "kind"),
        ({"quantity": "mass"}, "quantity"),
        ({"quantity": "length", "unit": "parsec"}, "unit"),
        ({"kind": "label", "missing": True}, "missing"),
        ({"order": "sideways"}, "order"),
    ],
)
def test_role_checks_its_fields(kwargs, field):
    with pytest.raises(ConfigError) as exc:
        Role("x", **kwargs)
    assert exc.value.field == field


def test_grid_period_is_not_fooled_by_a_stray_row():
    """A row 30 ms after a scan of a 1 s grid must not make a 30 ms grid: it is refused, on its own line."""
    times = np.r_[np.arange(10.0), 4.03]
    times.sort()
    rec = Record({}, np.arange(2, 2 + times.size), {"time": "t"}, {}, None, (), {}, "r.csv")
    with pytest.raises(
        InputError, match=r"r.csv:7: column 't': time 4.03 s is 0.03 periods off|r.csv:7: .*same"
    ):
        uniform_grid(rec, times)


def test_millisecond_stamps_at_20_hz_are_on_the_grid():
    """20 Hz samples stamped to the millisecond are up to 0.5 ms (1 % of T) off their grid points."""
    k_true = np.r_[0:50, 53:200]
    times = np.round(0.05 * k_true + 1e-4, 3)
    rec = Record({}, np.arange(2, 2 + times.size), {"time": "t"}, {}, None, (), {}, "r.csv")
    k, T = uniform_grid(rec, times)
    assert k.tolist() == (k_true - k_true[0]).tolist() and abs(T - 0.05) < 1e-5
