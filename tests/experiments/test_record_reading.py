"""Reading a ``simulate`` record back: the round trip through the table format, the refusals of a bad
record, and the horizons of a record."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError
from motionsig_cli.experiments.record_reading import (
    read_record_1d,
    read_record_2d,
    record_horizons,
    truth_of,
    uniform_times,
)
from motionsig_cli.experiments.vehicle_record import RecordConfig, simulate_record
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.tables import Table, read_table, render


def _write(table: Table, path, edit=None):
    text = render(table, "csv")
    path.write_text(edit(text) if edit else text)
    return read_table(path)


@pytest.fixture(scope="module")
def rec1():
    return simulate_record(RecordConfig(Vehicle1D(R=1e-3, f_r=0.1), mode=3, tau_chips=7, duration=3.0)).table


@pytest.fixture(scope="module")
def rec2():
    return simulate_record(RecordConfig(Vehicle2D(), mode=2, tau=45, duration=3.0, anr_pair=4)).table


def test_1d_round_trip(rec1, tmp_path):
    r = read_record_1d(_write(rec1, tmp_path / "a.csv"))
    assert np.array_equal(r.y, [row[2] for row in rec1.rows]) and r.times.size == 60
    assert r.vehicle.R == 1e-3 and r.vehicle.K == tuple(rec1.meta["K"]) and r.vehicle.T == 0.05
    assert r.truth == (2, 140) and r.m_rho == 20 and r.f_c == 1.0 and r.chips.shape == (3, 31)


def test_2d_round_trip_and_degrees(rec2, tmp_path):
    r = read_record_2d(_write(rec2, tmp_path / "b.csv"))
    assert r.y.shape == (60, 2) and r.truth == (1, 45)
    assert r.vehicle.R_range == rec2.meta["R_range"] and r.vehicle.start == (70.0, -20.0)
    brg = np.array([row[3] for row in rec2.rows])
    deg = Table(
        rec2.columns,
        [(*row[:3], math.degrees(row[3]), *row[4:]) for row in rec2.rows],
        {**rec2.meta, "bearing_unit": "deg"},
    )
    np.testing.assert_allclose(read_record_2d(_write(deg, tmp_path / "d.csv")).y[:, 1], brg, rtol=1e-12)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda s: s.replace("k,t,y,", "k,t,yy,"), "missing column 'y'"),
        (lambda s: s.replace("# R: 0.001\n", ""), "missing metadata 'R'"),
        (lambda s: s.replace("# m_rho: 20", "# m_rho: 0"), "bad metadata: m_rho = 0 is not in "),
        (lambda s: s.replace("# m_rho: 20", "# m_rho: 20.5"), "bad metadata: m_rho = 20.5 is not an integer"),
        (lambda s: s.replace("# R: 0.001", "# R: -1"), "bad metadata: R = -1"),
        (lambda s: s.replace('# codes: "corrected"', '# codes: "gold"'), "bad metadata"),
        (lambda s: s.replace("# T: 0.05", '# T: "fast"'), "metadata 'T' must be a positive number"),
    ],
)
def test_bad_1d_records(rec1, tmp_path, edit, message):
    with pytest.raises(InputError, match=message):
        read_record_1d(_write(rec1, tmp_path / "c.csv", edit))


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda s: s.replace("range,bearing,", "range,brg,"), "column 'bearing'"),
        (lambda s: s.replace('"rad"', '"grad"'), "bearing_unit"),
        (
            lambda s: s.replace("# start: [70.0, -20.0]", "# start: [70.0]"),
            "start must be a list of two numbers",
        ),
        (lambda s: s.replace("# m_rho: 20", "# m_rho: 2.5"), "m_rho must be an integer >= 1"),
        (lambda s: s.replace("# f_c: 1.0", "# f_c: -1"), "f_c must be finite and >= 0"),
        (lambda s: s.replace("# start: [70.0, -20.0]", "# start: [0, 0]"), "origin"),
    ],
)
def test_bad_2d_records(rec2, tmp_path, edit, message):
    with pytest.raises(InputError, match=message):
        read_record_2d(_write(rec2, tmp_path / "e.csv", edit))


def _cells(table: Table, column: str, row: int, value: float) -> Table:
    j = table.columns.index(column)
    rows = [
        tuple(value if (i == row and c == j) else v for c, v in enumerate(r))
        for i, r in enumerate(table.rows)
    ]
    return Table(table.columns, rows, table.meta)


@pytest.mark.parametrize(
    ("column", "value", "message"),
    [
        ("range", 0.0, "range 0 <= 0"),
        ("bearing", 57.3, "degrees in a column labelled radians"),
        ("range", math.inf, "column 'range' is not finite"),
        ("t", 0.0, "time is not increasing"),
        ("t", 0.21, "non-uniform time"),
    ],
)
def test_bad_cells_name_the_line(rec2, tmp_path, column, value, message):
    path = tmp_path / "f.csv"
    with pytest.raises(InputError, match=message) as exc:
        read_record_2d(_write(_cells(rec2, column, 4, value), path))
    assert str(path) in str(exc.value)


def test_too_short_a_record(rec1, tmp_path):
    short = Table(rec1.columns, rec1.rows[:1], rec1.meta)
    with pytest.raises(InputError, match="at least 2 samples"):
        uniform_times(_write(short, tmp_path / "g.csv"))


def test_truth_of():
    assert truth_of({"mode": 2, "tau": 40}) == (1, 40)
    assert truth_of({"mode": 2, "tau": 40, "signature": False}) is None
    assert truth_of({"tau": 40}) is None


def test_horizons():
    assert record_horizons(None, 80.0, 0.05) == [10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0]
    assert record_horizons(None, 7.5, 0.05) == [7.5]
    assert record_horizons([2.0, 5.0], 5.0, 0.05) == [2.0, 5.0]


@pytest.mark.parametrize(
    ("hs", "message"),
    [
        ([], "no horizon"),
        ([0.0], "> 0"),
        ([30.0], "longer than the record"),
        ([0.01], "shorter than one sample"),
    ],
)
def test_bad_horizons(hs, message):
    with pytest.raises(ConfigError, match=message) as exc:
        record_horizons(hs, 20.0, 0.05)
    assert exc.value.field == "horizons"
