"""track-sat on any receiver geometry (ATC-10 §4 beyond Table 4.1): the receivers' line of sight, positions
that change from epoch to epoch, the receivers each update uses, the recursion at each update's geometry,
and the configuration checks. Positions are made here with pymap3d (test-only), never by the code under
test."""

import numpy as np
import pymap3d
import pytest

from motionsig_cli.atc10 import satellite_tracking as st
from motionsig_cli.atc10.satellite_tracking import (
    ReceiverGeometry,
    RmsConfig,
    Timeline,
    TrackSatJob,
    Units,
    line_of_sight_blocked,
)
from motionsig_cli.config import ConfigError
from motionsig_cli.engine import run_job

A, B = 6378137.0, 6356752.314245179  # WGS-84 semi-axes [m]
AIRPORT = (48.3538, 11.7861, 453.0)
STATIONS_ENU = np.array(
    [[0.0, 0.0, -3.0], [8e3, 3e3, 70.0], [-6e3, 9e3, 35.0], [-4e3, -10e3, 150.0], [12e3, -7e3, -10.0]]
)


def _stations() -> np.ndarray:
    return np.column_stack(pymap3d.enu2ecef(*STATIONS_ENU.T, *AIRPORT))


def _ground(**kw) -> ReceiverGeometry:
    return ReceiverGeometry(
        _stations(), aircraft=(48.3538, 11.7861, 3.45), labels=("A", "B", "C", "D", "E"), **kw
    )


def _geo_sats(t: float = 0.0) -> np.ndarray:
    lat = np.array([27.0, 44.5, 62.6, 62.6, 56.2, 27.0, 44.5, 56.2]) + 2.0 * np.sin(
        2 * np.pi * t / 600 + np.arange(8)
    )
    lon = np.array([109.8, 129.5, 80.4, 114.6, 111.6, 85.3, 65.5, 83.4])
    return np.column_stack(pymap3d.geodetic2ecef(lat, lon, np.full(8, 35786e3)))


def _brute_blocked(r: np.ndarray, p: np.ndarray, samples: int = 20001) -> tuple[bool, float]:
    """Whether the segment r–p dips inside the ellipsoid, by sampling it, and by how much (in the coordinates
    scaled by (1/a, 1/a, 1/b)); a receiver below the surface is blocked only where the segment goes deeper
    than the receiver itself (the rule of :func:`line_of_sight_blocked`)."""
    t = np.linspace(0.0, 1.0, samples)[:, None]
    q = (r + t * (p - r)) / np.array([A, A, B])
    d = np.sqrt(np.sum(q * q, axis=-1))
    depth = min(1.0, d[0], d[-1]) - float(np.min(d[1:-1]))
    return bool(depth > 0), depth


def test_line_of_sight_equals_a_sampled_segment():
    """Random receivers (ground, low and geosynchronous) and aircraft (0-20 km): blocked exactly when a dense
    sample of the segment enters the ellipsoid (cases within the sampling resolution, 1e-7, left out)."""
    rng = np.random.default_rng(7)
    n = 400
    lat, lon = rng.uniform(-80, 80, n), rng.uniform(-180, 180, n)
    rx = np.column_stack(pymap3d.geodetic2ecef(lat, lon, rng.choice([-50.0, 0.0, 300.0, 20e3, 35786e3], n)))
    near = rng.uniform(0.0, 1.0, n) ** 2 * 60.0  # aircraft up to 60 degrees away, mostly near
    ac = np.column_stack(pymap3d.geodetic2ecef(
        np.clip(lat + near * np.cos(lon), -89, 89), lon + near * np.sin(lat), rng.uniform(0.0, 20e3, n)))  # fmt: skip
    got = line_of_sight_blocked(rx[:, None, :], ac)[:, 0]
    checked = 0
    for i in range(n):
        want, depth = _brute_blocked(rx[i], ac[i])
        if abs(depth) > 1e-7:
            assert got[i] == want, (i, depth)
            checked += 1
    assert checked > 300 and 0.2 < got.mean() < 0.8, got.mean()  # both outcomes well represented
    # a ground station sees an aircraft 3 km above a point 100 km away, not one 400 km away at 1 km
    g = _stations()[:1]
    near = np.array(pymap3d.enu2ecef(100e3, 0.0, 3e3 - 0.785e3, *AIRPORT))  # ~3 km above the surface there
    far = np.array(pymap3d.geodetic2ecef(*pymap3d.enu2geodetic(400e3, 0.0, 0.0, *AIRPORT)[:2], 1e3))
    assert not line_of_sight_blocked(g, near)[0] and line_of_sight_blocked(g, far)[0]


def test_receiver_geometry_checks_its_fields():
    pos = _stations()
    for kw, field in [
        ({"positions_m": pos[:2]}, "positions_m"),
        ({"positions_m": pos[:, :2]}, "positions_m"),
        ({"aircraft": (95.0, 0.0, 0.0)}, "aircraft"),
        ({"aircraft": (45.0, 0.0, 200.0)}, "aircraft"),
        ({"triplet": (0, 0, 1)}, "triplet"),
        ({"triplet": (0, 1, 7)}, "triplet"),
        ({"labels": ("a", "a", "b", "c", "d")}, "labels"),
        ({"positions_m": np.stack([pos, pos]), "times_s": np.array([0.0, 0.0])}, "times_s"),
        ({"positions_m": np.stack([pos, pos]), "times_s": np.array([1.0, 2.0])}, "times_s"),
    ]:
        args = {"positions_m": pos, **kw}
        with pytest.raises(ConfigError) as e:
            ReceiverGeometry(**args)
        assert e.value.field == field, kw


def test_track_interpolates_between_epochs_and_uses_receivers_listed_at_both():
    p0, p1 = _geo_sats(0.0), _geo_sats(10.0)
    p1[7] = np.nan  # G8 absent at the second epoch
    geo = ReceiverGeometry(np.stack([p0, p1, _geo_sats(20.0)]), np.array([0.0, 10.0, 20.0]))
    pos, present = geo.track_m(np.array([0.0, 2.5, 10.0, 15.0, 20.0]))
    np.testing.assert_array_equal(pos[0], p0)
    np.testing.assert_allclose(pos[1, :7], 0.75 * p0[:7] + 0.25 * p1[:7], rtol=1e-15)
    np.testing.assert_array_equal(pos[2, :7], p1[:7])
    assert present[:, 7].tolist() == [True, False, False, False, True] and present[:, :7].all()
    assert np.isnan(pos[1, 7]).all()
    with pytest.raises(ConfigError) as e:
        geo.track_m(np.array([0.0, 21.0]))
    assert e.value.field == "epochs" and "last epoch" in e.value.reason


def test_epoch_sets_follow_the_receivers_present_and_refuse_too_few():
    pos = np.stack([_stations()] * 11)
    pos[4:7, 3:] = np.nan  # D and E missing at epochs 4-6: three receivers (blind updates)
    geo = ReceiverGeometry(pos, np.arange(11.0), aircraft=(48.3538, 11.7861, 3.45))
    job = TrackSatJob(geo, sigma=5.0, sigma0=5.0, timeline=Timeline(10, 8, 1), runs=2, seed=1)
    assert job.sets is not None
    assert job.sets.counts().tolist() == [5, 5, 5, 5, 3, 3, 3, 5, 5, 3, 5]
    assert job.sets.blind.tolist() == [c == 3 for c in job.sets.counts()]
    assert job.sets.at(9).tolist() == [0, 1, 2]  # the outage triplet, in its order
    bad = pos.copy()
    bad[8:10, 1] = np.nan  # B, in the outage triplet, absent during the outage (update 9)
    with pytest.raises(ConfigError, match="outage receiver"):
        TrackSatJob(ReceiverGeometry(bad, np.arange(11.0), aircraft=(48.3538, 11.7861, 3.45)),
                    timeline=Timeline(10, 8, 1), runs=2)  # fmt: skip
    early = pos.copy()
    early[0, 3:] = np.nan  # three receivers at update 0: no least-squares start
    with pytest.raises(ConfigError, match="update 0") as e:
        TrackSatJob(ReceiverGeometry(early, np.arange(11.0), aircraft=(48.3538, 11.7861, 3.45)),
                    timeline=Timeline(10, 8, 1), runs=2)  # fmt: skip
    assert e.value.field == "constellation"
    few = pos.copy()
    few[2, 2:] = np.nan  # two receivers at update 2
    with pytest.raises(ConfigError, match="2 receiver"):
        TrackSatJob(ReceiverGeometry(few, np.arange(11.0), aircraft=(48.3538, 11.7861, 3.45)),
                    timeline=Timeline(10, 8, 1), runs=2)  # fmt: skip


def test_recursion_at_each_update_equals_the_static_recursion_for_a_table_that_does_not_move():
    """The same positions at every epoch: the per-update recursion (β_n, tr_n, b_n) equals the constant one,
    and the Monte Carlo hardly changes (the interpolation's rounding only)."""
    static = _ground()
    tl = Timeline(30, 20, 5)
    moving = ReceiverGeometry(np.stack([_stations()] * 31), np.arange(31.0), aircraft=static.aircraft,
                              labels=static.labels)  # fmt: skip
    kw = {"sigma": 5.0, "sigma0": 5.0, "timeline": tl, "runs": 200, "seed": 3}
    js, jm = TrackSatJob(static, **kw), TrackSatJob(moving, **kw)
    a_s, l_s = st.analytic_curve(js)
    a_m, l_m = st.analytic_curve(jm)
    np.testing.assert_allclose(a_m, a_s, rtol=1e-12)
    np.testing.assert_allclose(l_m, l_s, rtol=1e-12, equal_nan=True)
    rs, rm = run_job(js), run_job(jm)
    for e in rs.rms:
        np.testing.assert_allclose(rm.rms[e], rs.rms[e], rtol=1e-8, equal_nan=True)


def test_ground_job_is_independent_of_chunking_and_starts_near_the_truth():
    geo = _ground()
    kw = {"sigma": 5.0, "sigma0": 5.0, "timeline": Timeline(12, 6, 3), "runs": 30, "seed": 4}
    a, b = run_job(TrackSatJob(geo, chunk=30, **kw)), run_job(TrackSatJob(geo, chunk=7, **kw))
    for e in a.rms:
        np.testing.assert_array_equal(a.rms[e], b.rms[e])
    # the start: a tenth of the nearest receiver's range (the aircraft 3 km above station A)
    assert TrackSatJob(geo, **kw).init_offset_km == pytest.approx(0.1 * (3.45 - 0.45), rel=1e-6)
    assert (
        TrackSatJob(st.example("I", r_sat_km=42164.17), runs=2, timeline=Timeline(4, 2, 1)).init_offset_km
        == 50.0
    )
    ident = TrackSatJob(geo, **kw).identity()
    assert ident["receivers"] == list("ABCDE") and len(ident["receivers_sha256"]) == 64


def test_a_moving_aircraft_must_stay_in_sight_of_ground_receivers():
    with pytest.raises(ConfigError, match="altitude") as e:  # 40 m/s down for 160 s: 6.4 km, below -1 km
        TrackSatJob(_ground(), velocity_enu=(0.0, 0.0, -40.0), runs=2)
    assert e.value.field == "velocity_enu"
    far = ReceiverGeometry(_stations(), aircraft=(48.3538, 11.7861, 0.2))
    with pytest.raises(ConfigError, match="lose sight") as e:
        # 900 m/s east, 15 m/s down: 360 km east after 400 s at ~4 km (never below -1 km), far beyond the
        # stations' horizon (about 75 km + 236 km)
        TrackSatJob(far, velocity_enu=(900.0, 0.0, -15.0), timeline=Timeline(400, 100, 60), runs=2)
    assert e.value.field == "velocity_enu"


def test_rms_config_takes_a_geometry_and_units():
    geo = _ground()
    with pytest.raises(ConfigError) as e:
        RmsConfig(constellation=geo, params="table")
    assert e.value.field == "params"
    moving = ReceiverGeometry(np.stack([_stations()] * 2), np.array([0.0, 1.0]))
    with pytest.raises(ConfigError) as e:
        RmsConfig(constellation=moving)
    assert e.value.field == "constellation"
    with pytest.raises(ConfigError) as e:
        RmsConfig(units="furlongs")
    assert e.value.field == "units"
    rep_si = st.rms_report(RmsConfig(constellation=geo, sigma=5.0, units=Units.si))
    rep_ft = st.rms_report(RmsConfig(constellation=geo, sigma=5.0))
    i = rep_si.table.columns.index("rms_m")
    j = rep_ft.table.columns.index("rms_ft")
    np.testing.assert_allclose([r[i] for r in rep_si.table.rows], [r[j] * 0.3048 for r in rep_ft.table.rows],
                               rtol=1e-15)  # fmt: skip
    assert rep_si.figure["unit"] == "m" and "unit" not in rep_ft.figure


def test_unit_conversions():
    assert st.in_unit(50.0, Units.si, "time") == 5e-08 and st.in_unit(50.0, Units.report, "time") == 50.0
    assert st.in_unit(1.0, Units.si, "length") == 0.3048 and st.in_unit(2.0, Units.si, "distance") == 2000.0
    assert st.unit_suffix(Units.si, "length") == "m" and st.unit_suffix(Units.report, "time") == "ns"
