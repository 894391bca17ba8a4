"""Reading a ``simulate`` record back: the round trip through the table format, the refusals of a bad
record, and the horizons of a record."""

import math
import re

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.modesig.record_reading import (
    MAX_MAGNITUDE,
    read_record_1d,
    read_record_2d,
    record_horizons,
    truth_of,
    uniform_times,
)
from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record
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
        # issue 39: metadata that contradicts itself (tau = tau_chips * m_rho) is refused with both values
        (
            lambda s: s.replace("# m_rho: 20", "# m_rho: 10"),
            r"tau 140 samples, but tau_chips 7.0 x m_rho 10 = 70",
        ),
        (lambda s: s.replace("# tau_chips: 7.0", "# tau_chips: 6.0"), r"tau_chips 6.0 x m_rho 20 = 120"),
        (
            lambda s: s.replace("# tau_chips: 7.0", '# tau_chips: "7"'),
            r"tau_chips '7' x m_rho 20 = \? samples",
        ),
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
            r"start = \[70.0\] is not a list of two numbers",
        ),
        (lambda s: s.replace("# m_rho: 20", "# m_rho: 2.5"), "m_rho = 2.5 is not an integer"),
        (lambda s: s.replace("# f_c: 1.0", "# f_c: -1"), r"f_c = -1 is not in \[0, inf\)"),
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
        ("range", 0.0, "range 0 <= 0: the target is at the radar"),
        ("range", -5.0, "column 'range': range -5 m is not > 0"),
        ("range", 1e300, r"column 'range': \|range\| 1e\+300 m exceeds 1e\+09 m"),
        ("bearing", 57.3, "degrees in a column labelled radians"),
        ("range", math.inf, "column 'range': 'inf' is not finite"),
        ("t", 0.0, "time is not increasing"),
        ("t", 0.21, "periods off the 0.05 s grid"),
    ],
)
def test_bad_cells_name_the_line(rec2, tmp_path, column, value, message):
    path = tmp_path / "f.csv"
    with pytest.raises(InputError, match=message) as exc:
        read_record_2d(_write(_cells(rec2, column, 4, value), path))
    assert str(path) in str(exc.value)


@pytest.mark.parametrize("value", [1e300, -1e300, 1.5e9])
def test_an_implausible_1d_position_names_the_line(rec1, tmp_path, value):
    """|y| > 1e9 m (MAX_MAGNITUDE) is refused before it reaches the filters (row 4: line 4 after the
    metadata and the header)."""
    path = tmp_path / "h.csv"
    edited = _write(_cells(rec1, "y", 4, value), path)
    with pytest.raises(InputError, match=r"column 'y': \|y\| .* m exceeds 1e\+09 m") as exc:
        read_record_1d(edited)
    assert f"{path}:{edited.lines[4]}:" in str(exc.value)
    assert MAX_MAGNITUDE == 1e9
    ok = read_record_1d(_write(_cells(rec1, "y", 4, -MAX_MAGNITUDE), tmp_path / "ok.csv"))
    assert ok.y[4] == -1e9  # at the bound: read


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


# ------------------------------------------------------------------------- users' records (any layout)
from motionsig_cli.modesig.record_reading import (  # noqa: E402
    ModelOptions,
    read_vehicle_record,
)


def _table(columns, rows, meta=None, source="user.csv"):
    """A table as read from a file: data rows from line 2 on (after the header)."""
    return Table(tuple(columns), [tuple(str(c) for c in r) for r in rows], meta or {},
                 tuple(range(2, 2 + len(rows))), source, 1)  # fmt: skip


def _grid(n, T=0.05):
    return [k * T for k in range(n)]


def test_an_exact_column_name_wins_over_an_alias_and_an_alias_is_found():
    t = _grid(40)
    both = read_vehicle_record(_table(("t", "z", "y"), [(a, 9.0, k) for k, a in enumerate(t)]))
    assert np.array_equal(both.y, np.arange(40.0))  # y, not its alias z
    alias = read_vehicle_record(_table(("timestamp", "position"), [(a, 2 * k) for k, a in enumerate(t)]))
    assert np.array_equal(alias.y, 2 * np.arange(40.0))


@pytest.mark.parametrize(
    ("columns", "meta", "options", "layout"),
    [
        (("t", "y"), {}, {}, "1d"),
        (("t", "x", "y"), {}, {}, "cartesian"),
        (("t", "x", "y"), {"example": "1d"}, {}, "1d"),  # the metadata says
        (("t", "x", "pos"), {}, {"columns": "y=pos"}, "1d"),  # y mapped alone: a 1-D position
        (("t", "x", "y"), {}, {"example": "1d"}, "1d"),
        (("t", "range", "bearing", "x", "y"), {}, {}, "polar"),  # the measurements, not the true x, y
        (("t", "r", "b"), {}, {"columns": "range=r,bearing=b"}, "polar"),
    ],
)
def test_the_layout(columns, meta, options, layout):
    rows = [(a, 50.0 + k, 0.1) + (1.0,) * (len(columns) - 3) for k, a in enumerate(_grid(40))]
    rec = read_vehicle_record(_table(columns, [r[: len(columns)] for r in rows], meta), **options)
    assert (rec.y.ndim == 1) == (layout == "1d")
    assert ("measurement" in rec.provenance) == (layout == "cartesian")


def test_x_y_are_converted_exactly_and_the_start_is_the_first_position():
    x, y = np.array([70.0, 69.5, -3.0]), np.array([-20.0, -19.0, 4.0])
    rec = read_vehicle_record(_table(("time", "x", "y"), list(zip(_grid(3), x, y, strict=True))))
    assert np.array_equal(rec.y[:, 0], np.hypot(x, y)) and np.array_equal(rec.y[:, 1], np.arctan2(y, x))
    assert rec.vehicle.start == (pytest.approx(70.0, abs=1e-12), pytest.approx(-20.0, abs=1e-12))
    assert rec.provenance["model_sources"]["start"] == "record (the first measured position, assumed)"


def test_gaps_and_empty_cells_are_missing_samples():
    t = _grid(10)
    rows = [(a, float(k)) for k, a in enumerate(t) if k != 4]  # sample 4 absent
    rows[6] = (rows[6][0], "")  # sample 7 (line 8): an empty cell
    rec = read_vehicle_record(_table(("t", "y"), rows))
    assert rec.y.shape == (10,) and np.flatnonzero(np.isnan(rec.y)).tolist() == [4, 7]
    assert rec.lines.tolist() == [2, 3, 4, 5, 0, 6, 7, 8, 9, 10]
    assert rec.vehicle.T == 0.05 and rec.provenance["missing_samples"] == 2
    err = rec.missing_error("cannot skip")
    where = "user.csv:6: column 't': no row for t = 0.2 s (absent before this line)"
    assert str(err) == f"{where}: missing measurement (2 missing): cannot skip"
    assert rec.missing_error("x", n_used=4) is None
    rows = [(a, 50.0, "" if k == 3 else 0.1) for k, a in enumerate(t)]  # 2-D: a bearing missing
    rec2 = read_vehicle_record(_table(("t", "range", "bearing"), rows))
    assert np.isnan(rec2.y[3]).all() and not np.isnan(np.delete(rec2.y, 3, axis=0)).any()
    assert rec2.first_missing == (3, "user.csv:5: column 'bearing'")


def test_the_sample_period():
    t = [k * 0.05 for k in range(40)]  # 0.05 * k: the least-squares estimate is 0.05 within rounding
    rec = read_vehicle_record(_table(("t", "y"), [(a, 0.0) for a in t]))
    assert rec.vehicle.T == 0.05 and rec.provenance["model_sources"]["T"].startswith("record (estimated")
    finer = read_vehicle_record(_table(("t", "y"), [(a, 0.0) for a in t]), model=ModelOptions(T=0.025))
    assert finer.y.size == 79 and int(np.isnan(finer.y).sum()) == 39  # every other sample absent
    with pytest.raises(ConfigError) as exc:
        read_vehicle_record(_table(("t", "y"), [(a, 0.0) for a in t]), model=ModelOptions(T=0.07))
    assert exc.value.field == "T" and "the times give T = 0.05 s" in exc.value.reason
    meta = {"T": 0.1}
    with pytest.raises(InputError, match=r"T = 0\.1 s from the metadata"):
        read_vehicle_record(_table(("t", "y"), [(a, 0.0) for a in t], meta))


def test_model_sources_option_record_default(rec1, tmp_path):
    """A complete simulate record: every quantity from the record, no provenance added; an option wins over
    the record and says so; another code set drops the record's truth."""
    plain = read_vehicle_record(_write(rec1, tmp_path / "a.csv"))
    assert plain.provenance == {} and plain.truth == (2, 140) and plain.codes == "corrected"
    opts = ModelOptions(R=1e-2, f_c=1.0, codes="gold:45,75:3")
    rec = read_vehicle_record(_write(rec1, tmp_path / "a.csv"), model=opts)
    src = rec.provenance["model_sources"]
    assert rec.vehicle.R == 1e-2 and src["R"] == "option (the record says 0.001)"
    assert src["f_c"] == "option (as the record)" and src["codes"] == "option (the record says 'corrected')"
    assert src["T"] == "record" and rec.truth is None and rec.codes == "gold:45,75:3"


def test_a_simulate_record_missing_a_key_needs_its_option(rec1, tmp_path):
    def edit(s):
        return s.replace("# R: 0.001\n", "")

    with pytest.raises(InputError, match="missing metadata 'R'"):
        read_vehicle_record(_write(rec1, tmp_path / "c.csv", edit))
    rec = read_vehicle_record(_write(rec1, tmp_path / "c.csv", edit), model=ModelOptions(anr_db=20.0))
    assert rec.vehicle.R == pytest.approx(0.125 / 100) and rec.provenance["model_sources"]["R"].startswith(
        "option"
    )


def test_a_users_metadata_fills_what_it_has():
    meta = {"T": 0.05, "m_rho": 10, "K": [40, 10], "R": 0.002, "codes": "gps:1,2"}
    rec = read_vehicle_record(_table(("t", "y"), [(a, 0.0) for a in _grid(40)], meta))
    assert (rec.m_rho, rec.vehicle.K, rec.vehicle.R, rec.chips.shape) == (10, (40.0, 10.0), 0.002, (2, 1023))
    src = rec.provenance["model_sources"]
    assert src["m_rho"] == "record" and src["f_c"] == "default (assumed)" and rec.truth is None
    bad_values = (
        ("K", [1], "K = [1] is not a list of two numbers"),
        ("codes", "gold", "codes = 'gold'"),
        ("a_sig", "big", "a_sig = 'big' is not a number"),
    )
    for key, bad, text in bad_values:
        with pytest.raises(InputError, match=f"user.csv: bad metadata: {re.escape(text)}"):
            read_vehicle_record(_table(("t", "y"), [(a, 0.0) for a in _grid(40)], {**meta, key: bad}))


def test_bearing_units_and_limits():
    rows = [(a, 70.0, 10.0) for a in _grid(40)]
    deg = read_vehicle_record(_table(("t", "range", "bearing"), rows), units="bearing=deg")
    assert deg.y[0, 1] == pytest.approx(math.radians(10.0), rel=1e-15)
    with pytest.raises(
        InputError,
        match=r"user.csv:2: column 'bearing': bearing 10 is outside \[-3.14159, 3.14159\] rad \(degrees",
    ):
        read_vehicle_record(_table(("t", "range", "bearing"), rows))
    rows[5] = (rows[5][0], 70.0, 200.0)
    with pytest.raises(
        InputError, match=r"user.csv:7: column 'bearing': bearing 200 is outside \[-180, 180\] deg$"
    ):
        read_vehicle_record(_table(("t", "range", "bearing"), rows), units="bearing=deg")


def test_default_horizons_of_coarse_or_long_records():
    assert record_horizons(None, 40.0, 10.0) == [10.0, 20.0, 30.0, 40.0]
    assert record_horizons(None, 2e9, 1e9) == [1e9, 2e9]  # never shorter than a sample
    assert len(record_horizons(None, 50_000.0, 0.05)) == 1000  # at most 1000 by default
