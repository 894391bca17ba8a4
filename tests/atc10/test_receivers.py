"""Receivers tables: ECEF, WGS-84 and spherical forms, per-epoch positions, units, and the plausibility
checks (files written here with the csv module and json, not by the commands)."""

import csv
import json

import numpy as np
import pymap3d
import pytest

from motionsig_cli.atc10 import receivers as rx
from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError

STATIONS = [("S1", 48.3538, 11.7861, 453.0), ("S2", 48.4, 11.99, 500.9), ("S3", 48.228, 11.826, 529.1),
            ("S4", 48.273, 11.705, 472.2), ("S5", 48.462, 11.908, 465.6)]  # fmt: skip


def _write(path, header, rows, meta=()):
    with open(path, "w", newline="") as f:
        for line in meta:
            f.write(line + "\n")
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    return path


def _ecef(lat, lon, alt):
    return np.stack(pymap3d.geodetic2ecef(np.asarray(lat), np.asarray(lon), np.asarray(alt)), axis=-1)


def test_geodetic_and_ecef_tables_give_the_same_positions(tmp_path):
    geo = _write(tmp_path / "geo.csv", ["station", "lat", "lon", "alt"], STATIONS)
    xyz = _ecef([s[1] for s in STATIONS], [s[2] for s in STATIONS], [s[3] for s in STATIONS])
    ecef = _write(tmp_path / "ecef.csv", ["id", "x", "y", "z"],
                  [(s[0], *map(repr, map(float, p))) for s, p in zip(STATIONS, xyz, strict=True)])  # fmt: skip
    a, b = rx.read_receivers(geo), rx.read_receivers(ecef)
    assert a.ids == b.ids == ("S1", "S2", "S3", "S4", "S5") and a.form == "geodetic" and b.form == "ecef"
    assert a.static and a.E == 1 and a.K == 5
    np.testing.assert_allclose(a.ecef[0], xyz, rtol=0, atol=1e-6)
    np.testing.assert_allclose(b.ecef[0], xyz, rtol=0, atol=0)
    np.testing.assert_allclose(b.lat_deg[0], [s[1] for s in STATIONS], atol=1e-9)
    np.testing.assert_allclose(b.alt_m[0], [s[3] for s in STATIONS], atol=1e-6)
    assert a.lat_deg[0].tolist() == [s[1] for s in STATIONS]  # exactly the digits written
    prov = a.provenance()
    assert prov["receivers_form"] == "WGS-84 latitude, longitude, altitude" and prov["receivers_count"] == 5


def test_units_from_the_header_the_option_and_json(tmp_path):
    xyz = _ecef([s[1] for s in STATIONS], [s[2] for s in STATIONS], [s[3] for s in STATIONS])
    km = [(s[0], *(repr(float(v) / 1e3) for v in p)) for s, p in zip(STATIONS, xyz, strict=True)]
    h = rx.read_receivers(_write(tmp_path / "h.csv", ["receiver", "x [km]", "y [km]", "z [km]"], km))
    o = rx.read_receivers(_write(tmp_path / "o.csv", ["receiver", "x", "y", "z"], km), units="x=km,y=km,z=km")
    np.testing.assert_allclose(h.ecef[0], xyz, rtol=1e-15)
    np.testing.assert_allclose(o.ecef[0], xyz, rtol=1e-15)
    doc = {"meta": {}, "columns": ["site", "latitude [rad]", "longitude [rad]", "height [ft]"],
           "data": [{"site": s[0], "latitude [rad]": np.radians(s[1]), "longitude [rad]": np.radians(s[2]),
                     "height [ft]": s[3] / 0.3048} for s in STATIONS]}  # fmt: skip
    p = tmp_path / "r.json"
    p.write_text(json.dumps(doc))
    j = rx.read_receivers(p, columns="receiver=site")
    np.testing.assert_allclose(j.ecef[0], xyz, rtol=0, atol=1e-6)


def test_sphere_form_keeps_the_reports_sub_satellite_points(tmp_path):
    """The report's form: latitude, longitude on one orbit radius (the caller's), the digits kept."""
    p = _write(tmp_path / "sats.csv", ["satellite", "latitude_deg", "longitude_deg"],
               [("1", "0", "100"), ("2", "30.5", "140.25"), ("3", "-10", "90"), ("4", "12.3456789", "-75")])  # fmt: skip
    with pytest.raises(InputError, match=r"sats.csv:1: missing column 'altitude'"):
        rx.read_receivers(p)
    r = rx.read_receivers(p, sphere_radius_m=4.2164e7)
    assert r.form == "sphere" and r.lat_deg[0].tolist() == [0.0, 30.5, -10.0, 12.3456789]
    np.testing.assert_allclose(np.linalg.norm(r.ecef[0], axis=1), 4.2164e7, rtol=1e-15)
    assert np.isnan(r.alt_m).all()


def test_positions_per_epoch(tmp_path):
    rows = []
    for e in range(3):
        for s in STATIONS[: 4 + (e == 1)]:
            rows.append((e, s[0], s[1] + 0.001 * e, s[2], s[3]))
    p = _write(tmp_path / "moving.csv", ["epoch", "receiver", "lat", "lon", "alt"], rows)
    r = rx.read_receivers(p)
    assert r.E == 3 and r.K == 5 and r.epochs.tolist() == [0, 1, 2] and not r.static
    assert r.present.tolist() == [[True] * 4 + [False], [True] * 5, [True] * 4 + [False]]
    np.testing.assert_allclose(r.lat_deg[2, :4], [s[1] + 0.002 for s in STATIONS[:4]])
    assert r.lines[1].tolist() == [6, 7, 8, 9, 10]
    first = rx.read_receivers(p, multi_epoch="first")
    assert first.E == 1 and first.K == 4
    with pytest.raises(InputError, match=r"moving.csv:6: column 'epoch': a second epoch"):
        rx.read_receivers(p, multi_epoch="refuse")
    with pytest.raises(
        InputError, match=r"moving.csv:2: column 'epoch': 4 receiver\(s\) at epoch 0: at least 5"
    ):
        rx.read_receivers(p, min_receivers=5)


BAD = {
    "km": (["id", "x", "y", "z"], [("A", 4510.731, 4510.731, 0.0), ("B", -4510.731, 4510.731, 10.0)],
           {}, r"bad.csv:2: column 'x': positions look like kilometres: \|r\| = 6379.14 m"),
    "inside": (["id", "x", "y", "z"], [("A", 1e3, 2e3, 3e3)], {}, r"bad.csv:2: column 'x': \|r\| = 3741.66 m .* inside the Earth"),
    "beyond": (["id", "x", "y", "z"], [("A", 2e8, 0, 0)], {}, r"bad.csv:2: column 'x': .* beyond 1e\+08 m"),
    "altitude km": (["id", "lat", "lon", "alt [km]"], [("A", 10, 10, 3e5)], {}, r"bad.csv:2: column 'alt \[km\]': .* beyond"),
    "latitude": (["id", "lat", "lon", "alt"], [("A", 48.0, 11.0, 0), ("B", 91.0, 11.0, 0)], {},
                 r"bad.csv:3: column 'lat': latitude 91 deg is outside \[-90, 90\]"),
    "longitude": (["id", "lat", "lon", "alt"], [("A", 48.0, 400.0, 0)], {}, r"bad.csv:2: column 'lon': longitude 400"),
    "coincident": (["id", "lat", "lon", "alt"], [("A", 48.0, 11.0, 450.0), ("B", 48.1, 11.0, 450.0), ("C", 48.0, 11.0, 450.0002)],
                   {}, r"bad.csv:4: column 'lat': receivers 'A' \(line 2\) and 'C' \(line 4\) coincide"),
    "duplicate": (["id", "lat", "lon", "alt"], [("A", 48.0, 11.0, 450.0), ("B", 48.1, 11.0, 450.0), ("A", 48.2, 11.0, 450.0)],
                  {}, r"bad.csv:4: column 'id': receiver 'A' appears twice \(lines 2 and 4\)"),
    "only x, y": (["id", "x", "y"], [("A", 6.4e6, 0)], {}, r"bad.csv:1: missing column 'z'"),
    "no position": (["id", "range"], [("A", 1.0)], {}, r"bad.csv:1: no receiver positions"),
    "text": (["id", "lat", "lon", "alt"], [("A", "48.0", "eleven", 450.0)], {}, r"bad.csv:2: column 'lon': 'eleven' is not a number"),
    "missing": (["id", "lat", "lon", "alt"], [("A", "48.0", "", 450.0)], {}, r"bad.csv:2: column 'lon': missing value"),
    "unknown unit": (["id", "x [furlong]", "y", "z"], [("A", 1, 2, 3)], {}, r"bad.csv:1: column 'x \[furlong\]': unknown length unit"),
    "disagree": (["id", "x", "y", "z", "lat", "lon", "alt"], [("A", 6378137.0, 0, 0, 0.0, 0.001, 0.0)], {},
                 r"bad.csv:2: column 'lat': the geodetic position is 111.3 m from the ECEF"),
    "multi without ids": (["epoch", "x", "y", "z"], [(0, 6378137.0, 0, 0), (1, 6378137.0, 0, 0)], {},
                          r"bad.csv:1: missing column 'receiver'"),
    "time backwards": (["time", "id", "x", "y", "z"], [(1.0, "A", 6378137.0, 0, 0), (0.5, "A", 6378137.0, 0, 0)], {},
                       r"bad.csv:3: column 'time': time goes backwards"),
    "epoch with two times": (["epoch", "time", "id", "x", "y", "z"],
                             [(0, 1.0, "A", 6378137.0, 0, 0), (0, 1.0, "B", 6378137.0, 1e3, 0), (0, 1.5, "C", 6378137.0, 0, 1e3),
                              (0, 1.0, "D", 6378137.0, 1e3, 1e3)], {},
                             r"bad.csv:4: column 'time': epoch 0 has two times: 1.5 s here, 1.0 s at line 2 and 2 more"),
    "no label where required": (["lat", "lon", "alt"], [(48.0, 11.0, 450.0)], {"require_label": True},
                                r"bad.csv:1: no receiver column: map one with --columns receiver=NAME \(columns: lat, lon, alt"),
    "no label, other option": (["lat", "lon", "alt"], [(48.0, 11.0, 450.0)],
                               {"require_label": True, "columns_option": "--receivers-columns"},
                               r"no receiver column: map one with --receivers-columns receiver=NAME"),
    "mapped column absent": (["site_no", "lat", "lon", "alt"], [(1, 48.0, 11.0, 450.0)],
                             {"columns": "receiver=site", "columns_option": "--receivers-columns"},
                             r"bad.csv:1: no column 'site' for --receivers-columns receiver=site"),
    "empty": (["id", "x", "y", "z"], [], {}, r"bad.csv: no receivers"),
}  # fmt: skip


@pytest.mark.parametrize("name", list(BAD))
def test_bad_tables_are_refused_with_file_line_and_column(tmp_path, name):
    header, rows, kw, match = BAD[name]
    p = _write(tmp_path / "bad.csv", header, rows)
    with pytest.raises(InputError, match=match):
        rx.read_receivers(p, **kw)


def test_an_empty_file_and_bad_options(tmp_path):
    p = tmp_path / "e.csv"
    p.write_text("")
    with pytest.raises(InputError, match=r"e\.csv: no header row"):
        rx.read_receivers(p)
    good = _write(tmp_path / "g.csv", ["id", "lat", "lon", "alt"], STATIONS)
    for kw, field in (({"multi_epoch": "x"}, "multi_epoch"), ({"min_receivers": 0}, "min_receivers"),
                      ({"columns": "bogus=lat"}, "columns"), ({"units": "lat=furlong"}, "units")):  # fmt: skip
        with pytest.raises(ConfigError) as exc:
            rx.read_receivers(good, **kw)
        assert exc.value.field == field


def test_the_row_limit(tmp_path):
    p = _write(
        tmp_path / "long.csv", ["id", "lat", "lon", "alt"], [(f"R{i}", 0.0, i * 1e-3, 0.0) for i in range(11)]
    )
    with pytest.raises(InputError, match=r"long.csv:12: more than 10 data rows"):
        rx.read_receivers(p, max_rows=10)


def test_time_shift_between_timestamp_origins():
    assert rx.time_shift("2026-05-01T12:00:01.5", "2026-05-01T12:00:00") == 1.5
    assert rx.time_shift(None, "2026-05-01T12:00:00") == 0.0
    with pytest.raises(ValueError, match="time zone"):
        rx.time_shift("2026-05-01T12:00:00Z", "2026-05-01T12:00:00")


def test_rows_are_numbered_only_where_no_label_is_required(tmp_path):
    """Without a receiver column a table of one epoch is numbered 1, 2, … (constellation, rms, simulate use
    the labels as names only); ``site`` is a receiver column."""
    p = _write(tmp_path / "n.csv", ["lat", "lon", "alt"], [s[1:] for s in STATIONS])
    assert rx.read_receivers(p).ids == ("1", "2", "3", "4", "5")
    q = _write(tmp_path / "s.csv", ["site", "lat", "lon", "alt"], STATIONS)
    assert rx.read_receivers(q, require_label=True).ids == tuple(s[0] for s in STATIONS)


def test_exact_values_keep_every_digit(tmp_path):
    """exact_values: the cells' decimals times the unit exactly (an integer of 19 digits in ns, a text of 22
    significant digits), a missing cell None; float64 of the same cells loses the last digits."""
    from decimal import Decimal

    from motionsig_cli.records import RecordSpec, Role, read_record

    p = tmp_path / "t.csv"
    p.write_text("t [ns],a [km]\n1777629600000009523,1234.567890123456789012\n1777629600000000001,\n")
    spec = RecordSpec((Role("t", quantity="time"), Role("a", quantity="length", missing=True)))
    rec = read_record(p, spec)
    assert rx.exact_values(rec, "t", "time") == [
        Decimal("1777629600.000009523"),
        Decimal("1777629600.000000001"),
    ]
    assert rx.exact_values(rec, "a", "length") == [Decimal("1234567.890123456789012"), None]
    exact = rx.exact_values(rec, "t", "time")
    assert float(exact[0] - exact[1]) == 9.522e-6
    assert abs((rec["t"][0] - rec["t"][1]) - 9.522e-6) > 1e-8  # float64 of the cells: off by ~0.1 µs
