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


def _rec(n):
    return Record({}, np.arange(2, 2 + n), {"time": "t"}, {}, None, (), {}, "r.csv")


@pytest.mark.parametrize(
    ("T", "n", "jitter", "gaps"),
    [(0.05, 1600, 2e-3, [(100, 110)]), (0.05, 1600, 2e-3, [(800, 830)]), (1.0, 5030, 2e-3, [(30, 5000)]),
     (1.0, 5030, 2e-3, [(10, 20), (40, 4000)])],
)  # fmt: skip
def test_jittered_records_with_gaps_land_on_their_grid(T, n, jitter, gaps):
    """Jitter up to 4 % of T (uniform ±2 ms) and gaps of 10 to 4970 periods: every seed gives the true steps,
    and T within 4 standard errors of a least-squares line through the stamps, σ_j √(12 / n³) for n stamps
    spaced one period apart with jitter σ_j = 2 ms / √3 (the longest run bounds it from above)."""
    for seed in range(20):
        g = np.random.default_rng(seed)
        keep = np.ones(n, bool)
        for a, b in gaps:
            keep[a:b] = False
        k_true = np.arange(n)[keep]
        times = 1000.0 + k_true * T + g.uniform(-jitter, jitter, k_true.size)
        k, T_hat = uniform_grid(_rec(times.size), times)
        run = max(
            b - a for a, b in zip([0, *(g1 for _, g1 in gaps)], [*(g0 for g0, _ in gaps), n], strict=True)
        )
        se = jitter / math.sqrt(3) * math.sqrt(12 / run**3)
        assert k.tolist() == (k_true - k_true[0]).tolist() and abs(T_hat - T) < 4 * se, seed


def test_a_gap_the_times_cannot_count_is_refused():
    """Five stamps of ±2 ms jitter at 1 s give T to about ±0.7 ms: a gap of 10⁴ s could be 9999 or 10001
    periods, so the count is refused (on the row after the gap) rather than guessed."""
    g = np.random.default_rng(3)
    k_true = np.r_[0:5, 10_000:10_005]
    times = k_true * 1.0 + g.uniform(-2e-3, 2e-3, k_true.size)
    with pytest.raises(
        InputError, match=r"r.csv:7: column 't': the .* s gap before this row is .* give the period"
    ):
        uniform_grid(_rec(times.size), times)
    k, T = uniform_grid(_rec(times.size), times, 1.0)  # with the period given, the gap is counted
    assert k.tolist() == k_true.tolist() and T == 1.0


def test_pandas_style_json_list_of_records(tmp_path):
    """pandas' ``to_json(orient="records")`` writes a bare list: it is read like the commands' JSON."""
    p = _write(tmp_path, json.dumps([{"t": 0, "x": 1, "y": None}, {"t": 1, "x": 2, "y": 3}]), "r.json")
    rec = read_record(p, SPEC)
    assert rec["x"].tolist() == [1.0, 2.0] and math.isnan(rec["y"][0])


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("t;x;y\n0;1;2\n", r"r.csv:1: the header 't;x;y' is one column: the file looks separated by ';'"),
        ("# units: x=km\nt,x,y\n0,1,2\n", r"r.csv:1: metadata 'units' must be a JSON object"),
        ("t,x,y\n0,1,2\n1,1,2\n,1,2\n", r"r.csv:4: column 't': missing time"),
    ],
)
def test_messages_that_say_what_is_wrong(tmp_path, text, match):
    with pytest.raises(InputError, match=match):
        read_record(_write(tmp_path, text), SPEC)


def test_time_zone_annotation_and_unit_spellings(tmp_path):
    """``Time (UTC)`` names a time scale, not a unit; ``sec``, ``°``, ``mm`` are units; unmapped columns are
    listed in the provenance."""
    rec = read_record(_write(tmp_path, "Time (UTC),x [mm],y,bearing [°],SNR\n0,1,2,90,3\n1,1,2,90,3\n"), SPEC)
    assert rec.units["time"] == "s" and rec["x"][0] == 1e-3 and rec["bearing"][0] == math.pi / 2
    assert rec.provenance()["input_ignored_columns"] == ["SNR"]
    rec = read_record(_write(tmp_path, "t [sec],x,y\n0,1,2\n2,1,2\n"), SPEC)
    assert rec["time"].tolist() == [0.0, 2.0]


# --- units people write, and unit suffixes in column names -----------------------------------------------

NMI = 1852.0
DEG = math.pi / 180.0
KT = 1852.0 / 3600.0
FT = 0.3048

POLAR = RecordSpec(
    (
        Role("time", ("t",), kind="time", order="increasing"),
        Role("range", ("r", "rho"), quantity="length"),
        Role("bearing", ("azimuth",), quantity="angle"),
        Role("altitude", ("alt",), quantity="length", required=False, missing=True),
        Role("speed", ("gs",), quantity="speed", required=False),
        Role("vertical_rate", ("vr",), quantity="speed", required=False),
        Role("sigma_phi", (), quantity="angle", required=False),
    ),
    max_rows=100,
)


@pytest.mark.parametrize(
    ("quantity", "text", "unit", "factor"),
    [
        ("length", "NM", "NM", NMI),
        ("length", "nm", "nm", NMI),
        ("length", "nmi", "nmi", NMI),
        ("length", "Nm", "NM", NMI),
        ("length", "FT", "ft", FT),
        ("speed", "kt", "kt", KT),
        ("speed", "KT", "kt", KT),
        ("speed", "kts", "kts", KT),
        ("speed", "Knots", "knots", KT),
        ("speed", "knot", "knot", KT),
        ("speed", "kn", "kn", KT),
        ("speed", "fpm", "fpm", FT / 60.0),
        ("speed", "ft/min", "ft/min", FT / 60.0),
        ("speed", "M/S", "m/s", 1.0),
        ("angle", "Deg", "deg", DEG),
        ("angle", "degrees", "degrees", DEG),
        ("angle", "°", "°", DEG),
        ("time", "MS", "ms", 1e-3),
    ],
)
def test_unit_spellings_and_case(quantity, text, unit, factor):
    from motionsig_cli.records import UNITS, canonical_unit

    assert canonical_unit(quantity, text) == unit
    assert UNITS[quantity][unit] == pytest.approx(factor, rel=1e-15)


@pytest.mark.parametrize(("quantity", "text"), [("length", "parsec"), ("angle", "grad"), ("speed", "mach")])
def test_unknown_units_are_not_guessed(quantity, text):
    from motionsig_cli.records import canonical_unit

    assert canonical_unit(quantity, text) is None


def test_unit_suffixes_in_column_names(tmp_path):
    text = "t_ms,range_nm,bearing_deg,alt_ft,speed_kt,vr_fpm,sigma_phi_deg\n0,10,90,35000,450,-1000,0.1\n500,20,180,,460,0,0.1\n"
    rec = read_record(_write(tmp_path, text), POLAR)
    assert rec.columns == {
        "time": "t_ms",
        "range": "range_nm",
        "bearing": "bearing_deg",
        "altitude": "alt_ft",
        "speed": "speed_kt",
        "vertical_rate": "vr_fpm",
        "sigma_phi": "sigma_phi_deg",
    }
    assert rec.units == {
        "time": "ms",
        "range": "nm",
        "bearing": "deg",
        "altitude": "ft",
        "speed": "kt",
        "vertical_rate": "fpm",
        "sigma_phi": "deg",
    }
    np.testing.assert_allclose(rec["time"], [0.0, 0.5])
    np.testing.assert_allclose(rec["range"], [10 * NMI, 20 * NMI])
    np.testing.assert_allclose(rec["bearing"], [math.pi / 2, math.pi])
    assert rec["altitude"][0] == pytest.approx(35000 * FT) and math.isnan(rec["altitude"][1])
    np.testing.assert_allclose(rec["speed"], [450 * KT, 460 * KT])
    np.testing.assert_allclose(rec["vertical_rate"], [-1000 * FT / 60, 0.0])
    assert rec["sigma_phi"][0] == pytest.approx(0.1 * DEG)
    assert rec.provenance()["input_units"]["range"] == "nm"


def test_suffix_case_and_upper_case_units(tmp_path):
    rec = read_record(_write(tmp_path, "T,Range_NM,Bearing_Deg\n0,1,45\n1,2,90\n"), POLAR)
    assert rec.units["range"] == "NM" and rec.units["bearing"] == "deg"
    np.testing.assert_allclose(rec["range"], [NMI, 2 * NMI])


def test_unit_precedence_option_header_suffix_metadata(tmp_path):
    """--units over the header over the name's suffix over the metadata over the default."""
    meta = '# units: {"range": "km", "bearing": "rad"}\n'
    p = _write(tmp_path, meta + "t,range_nm [km],bearing_deg\n0,1,90\n1,2,90\n")
    rec = read_record(p, POLAR)
    assert rec.units["range"] == "km" and rec["range"][0] == 1000.0  # header over suffix
    assert rec.units["bearing"] == "deg"  # suffix over metadata
    rec = read_record(p, POLAR, units="range=NM,bearing=mrad")  # option over all
    assert rec.units == {"time": "s", "range": "NM", "bearing": "mrad"}
    assert rec["range"][0] == NMI and rec["bearing"][0] == pytest.approx(0.09)
    rec = read_record(_write(tmp_path, meta + "t,range,bearing\n0,1,90\n1,2,90\n"), POLAR)
    assert rec.units["range"] == "km" and rec.units["bearing"] == "rad"  # metadata over the default


def test_units_option_is_tolerant_of_case(tmp_path):
    assert parse_units("range=Nm,bearing=DEG", POLAR) == {"range": "NM", "bearing": "deg"}
    with pytest.raises(ConfigError, match="units") as exc:
        parse_units("range=parsec", POLAR)
    assert exc.value.field == "units"


def test_exact_name_and_suffix_form_together_are_ambiguous(tmp_path):
    p = _write(tmp_path, "t,range,range_nm,bearing\n0,1,1,0\n1,2,2,0\n")
    with pytest.raises(InputError, match="'range' and 'range_nm' could both be the range"):
        read_record(p, POLAR)
    rec = read_record(p, POLAR, columns="range=range_nm")  # mapped: the suffix still gives the unit
    assert rec.columns["range"] == "range_nm" and rec.units["range"] == "nm"
    assert rec["range"].tolist() == [NMI, 2 * NMI]
    assert rec.extra == ("range",)


def test_a_role_name_is_not_another_roles_suffix_form():
    """``sigma_phi`` is the role sigma_phi, never ``sigma`` in ``phi``; ``alt_m`` is altitude in metres; a
    suffix that is not a unit of the role's quantity leaves the column alone."""
    from motionsig_cli.tables import Table

    spec = RecordSpec(
        (
            Role("time", ("t",), kind="time"),
            Role("alt", (), quantity="length"),
            Role("alt_m", (), quantity="length", required=False),
            Role("bearing", (), quantity="angle", required=False),
        )
    )
    rec = read_record(Table(columns=("t", "alt_m", "alt_ft", "bearing_ft"), rows=[(0, 1, 2, 3)]), spec)
    assert rec.columns == {"time": "t", "alt": "alt_ft", "alt_m": "alt_m"}
    assert rec.units["alt"] == "ft" and rec.units["alt_m"] == "m"
    assert rec.extra == ("bearing_ft",)  # ft is not an angle


def test_columns_option_to_an_alias_suffix_form(tmp_path):
    p = _write(tmp_path, "stamp,rng_nm,east_km,north_km,b\n0,1,2,3,4\n")
    rec = read_record(p, SPEC, columns="time=stamp,x=east_km,y=north_km,bearing=b", units="bearing=deg")
    assert rec.units["x"] == "km" and rec["x"][0] == 2000.0 and rec["y"][0] == 3000.0
    assert "rng_nm" in rec.extra  # not a role of SPEC


def test_slrt_detections_and_sensors_with_unit_suffixes(tmp_path):
    """The SLRT readers' specs read ``range_nm``, ``bearing_deg``, ``sigma_phi_deg``, ``fov_nm``."""
    from motionsig_cli.existence.slrt_record import DETECTION_SPEC, SENSOR_SPEC

    det = _write(tmp_path, "time,sensor,range_nm,bearing_deg\n1,A,10,30\n2,A,11,31\n", "d.csv")
    rec = read_record(det, DETECTION_SPEC)
    assert rec.units["range"] == "nm" and rec.units["bearing"] == "deg"
    np.testing.assert_allclose(rec["range"], [10 * NMI, 11 * NMI])
    np.testing.assert_allclose(rec["bearing"], [30 * DEG, 31 * DEG])
    sen = _write(
        tmp_path,
        "sensor,x_km,y_km,sigma_r_m,sigma_phi_deg,pd,clutter,fov_nm\nA,1,2,50,0.2,0.9,1,60\n",
        "s.csv",
    )
    rec = read_record(sen, SENSOR_SPEC)
    assert rec.units == {"x": "km", "y": "km", "sigma_r": "m", "sigma_phi": "deg", "fov": "nm"}
    assert rec["x"][0] == 1000.0 and rec["sigma_r"][0] == 50.0 and rec["fov"][0] == 60 * NMI
    assert rec["sigma_phi"][0] == pytest.approx(0.2 * DEG)
    sen = _write(
        tmp_path, "sensor,x,y,sigma_r,sigma_phi_mrad,pd,clutter,fov\nA,1,2,50,3,0.9,1,6e4\n", "s2.csv"
    )
    rec = read_record(sen, SENSOR_SPEC)
    assert rec.units["sigma_phi"] == "mrad" and rec["sigma_phi"][0] == pytest.approx(3e-3)
