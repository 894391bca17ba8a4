"""One track record for the manoeuvre trackers (maneuver.record): the scan grid from times or
scans, T from the option, the metadata or the data, missed scans, σ given or estimated, the IMM's noises.

Every record is written here with numpy and the csv/json modules, never by motionsig."""

import csv
import io
import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError
from motionsig_cli.maneuver import record as mr
from motionsig_cli.maneuver import record_tracking as rt
from motionsig_cli.maneuver import study as ex
from motionsig_cli.models.motion import Q_PAPER
from motionsig_cli.surveillance.report_hygiene import HygienePolicy


def _csv(tmp_path, header, rows, meta=(), name="r.csv"):
    buf = io.StringIO()
    for line in meta:
        buf.write(f"# {line}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    p = tmp_path / name
    p.write_text(buf.getvalue())
    return p


def _cv(N, sigma=50.0, seed=0, v=(120.0, -80.0), T=1.0):
    rng = np.random.default_rng(seed)
    t = np.arange(N) * T
    pos = np.stack([500.0 + v[0] * t, -700.0 + v[1] * t], axis=1)
    return pos, pos + sigma * rng.standard_normal((N, 2))


def test_timestamps_with_jitter_and_gaps_make_the_scan_grid(tmp_path):
    rng = np.random.default_rng(1)
    N, T = 60, 0.5
    k = np.array([i for i in range(N) if i not in (7, 8, 30)])  # three absent rows
    t = 10.0 + k * T + rng.uniform(-0.01, 0.01, k.size) * T  # jitter ≤ 1 % of T
    _, z = _cv(N, T=T)
    rows = [[f"{ti:.6f}", *(("", "") if i == 20 else z[i])] for ti, i in zip(t, k, strict=True)]
    rows[25][2] = "nan"  # one coordinate missing: a missed scan
    rec = mr.read_track_record(_csv(tmp_path, ["t", "east", "north"], rows))
    assert rec.T == pytest.approx(T, rel=1e-3) and rec.T_source.startswith("estimated")
    assert rec.z.shape == (N, 2)
    missed = np.flatnonzero(~rec.measured).tolist()
    assert missed == [7, 8, 20, 27, 30]  # the absent rows, the blank row, the half row (row 25 is scan 27)
    assert rec.scan.tolist() == list(range(1, N + 1))
    np.testing.assert_allclose(rec.t, t[0] + np.arange(N) * rec.T)
    np.testing.assert_array_equal(rec.z[10], z[10])


def test_a_given_period_must_agree_with_the_times(tmp_path):
    _, z = _cv(20)
    p = _csv(tmp_path, ["t", "x", "y"], [[i * 1.0, *z[i]] for i in range(20)])
    assert mr.read_track_record(p, T=1.0005).T == 1.0005  # within 0.1 %: the given value
    with pytest.raises(ConfigError) as exc:
        mr.read_track_record(p, T=1.01)
    assert exc.value.field == "T" and "disagrees" in exc.value.reason
    m = _csv(tmp_path, ["t", "x", "y"], [[i * 1.0, *z[i]] for i in range(20)], meta=["T: 2.0"], name="m.csv")
    with pytest.raises(InputError, match=r"m.csv: metadata 'T' = 2 s disagrees"):
        mr.read_track_record(m)
    # a record with more gaps than scans is read with the period given
    sparse = _csv(tmp_path, ["t", "x", "y"], [[k * 1.0, *z[k]] for k in (0, 3, 5, 8, 11, 13)], name="s.csv")
    rec = mr.read_track_record(sparse, T=1.0)
    assert rec.z.shape[0] == 14 and int(rec.measured.sum()) == 6


@pytest.mark.parametrize(
    ("times", "match"),
    [
        ([0, 1, 2, 2, 4, 5, 6, 7, 8, 9], r"r.csv:5: column 't': the row repeats the time of an earlier row"),
        ([0, 1, 2, 3, 3, 5, 6, 7, 8, 9], r"r.csv:6: column 't': the row has another position at the time"),
        ([0, 1, 2, 1.5, 4, 5, 6, 7, 8, 9], r"r.csv:5: column 't': time 1.5 s is earlier than the row before"),
    ],
)
def test_strict_reading_refuses_unsorted_and_repeated_times_naming_the_line(tmp_path, times, match):
    rows = [[ti, 10.0 * i, 2.0 * i] for i, ti in enumerate(times)]
    if times[3] == times[2]:
        rows[3][1:] = rows[2][1:]  # an exact duplicate
    p = _csv(tmp_path, ["t", "x", "y"], rows)
    strict = mr.ReadOptions(hygiene=HygienePolicy(strict=True))
    with pytest.raises(InputError, match=match):
        mr.read_track_record(p, strict)
    rec = mr.read_track_record(p)  # the default policy sorts and drops instead, and counts it
    assert (
        np.all(np.diff(rec.t) > 0)
        and sum(rec.hygiene[k] for k in ("reordered", "exact_duplicates", "conflicting_duplicates")) >= 1
    )


def test_times_off_a_grid_are_steps_at_their_own_times(tmp_path):
    """A time 0.3 periods off the grid, or two rows 0.02 s apart, no longer stop the record: the rows are
    then steps at their own times (Δt from the row before), not a scan grid."""
    for times in ([0, 1, 2, 3.3, 4, 5, 6, 7, 8, 9], [0, 1, 2, 3, 3.02, 4, 5, 6, 7, 8]):
        p = _csv(tmp_path, ["t", "x", "y"], [[ti, 10.0 * ti, 1.0 + ti] for ti in times])
        rec = mr.read_track_record(p)
        assert not rec.grid and rec.t.tolist() == [float(v) for v in times]
        assert rec.T_source.startswith("irregular times")
    on_grid = mr.read_track_record(_csv(tmp_path, ["t", "x", "y"], [[i, 10.0 * i, 1.0] for i in range(9)]))
    assert on_grid.grid and on_grid.T == 1.0


def test_scans_alone_make_the_grid_and_T_defaults(tmp_path):
    _, z = _cv(12)
    rows = [[s, *z[s - 1]] for s in (1, 2, 3, 5, 6, 7, 8, 9, 10, 12)]
    rec = mr.read_track_record(_csv(tmp_path, ["scan", "z_x", "z_y"], rows))
    assert rec.T == 1.0 and rec.T_source.startswith("assumed 1 s")
    assert np.flatnonzero(~rec.measured).tolist() == [3, 10] and rec.scan.tolist() == list(range(1, 13))
    meta = _csv(tmp_path, ["scan", "z_x", "z_y"], rows, meta=["T: 0.25"], name="m.csv")
    assert mr.read_track_record(meta).T == 0.25
    assert mr.read_track_record(meta, T=2.0).T == 2.0  # the option wins (no times to disagree with)
    both = _csv(
        tmp_path, ["scan", "t", "z_x", "z_y"], [[s, s - 1.0, *z[s - 1]] for s in (1, 2, 4, 5)], name="b.csv"
    )
    assert mr.read_track_record(both).scan.tolist() == [1, 2, 3, 4, 5]
    off = _csv(
        tmp_path,
        ["scan", "t", "z_x", "z_y"],
        [[s, 0.0 + i, *z[i]] for i, s in enumerate((1, 2, 4))],
        name="o.csv",
    )
    with pytest.raises(
        InputError, match=r"o.csv:4: column 'scan': scan 4 is 3 scans after the first, but its time"
    ):
        mr.read_track_record(off)


@pytest.mark.parametrize(
    ("header", "rows", "kwargs", "match"),
    [
        (
            ["a", "b", "c"],
            [[1, 2, 3]],
            {},
            r"r.csv:1: missing column 'time' \(or 't', 'timestamp'\) or 'scan'",
        ),
        (
            ["t", "a", "b"],
            [[1, 2, 3]],
            {},
            r"r.csv:1: missing column 'x' \(or 'z_x', 'east'\), or 'latitude'",
        ),
        (["x", "y"], [[1, 2]] * 3, {}, r"r.csv:1: missing column 'time' .* or 'scan'"),
        (
            ["t", "x", "y"],
            [[0, 1, 2], [1, "", 2], [2, "nan", 3]],
            {},
            r"need at least 3 scans with a measurement",
        ),
        (["t", "x", "y"], [[0, 1, 2], [1, 2e10, 2], [2, 3, 3]], {}, r"r.csv:3: column 'x': \|measurement\|"),
        (
            ["scan", "x", "y"],
            [[1, 1, 2], [2, 2, 2], [10**6, 3, 2]],
            {},
            r"r.csv:4: column 'scan': the record spans",
        ),
        (
            ["run", "scan", "x", "y"],
            [[0, 1, 1, 2], [0, 2, 1, 2], [1, 1, 1, 2]],
            {},
            r"r.csv:4: column 'run': several",
        ),
        (["t", "x", "y"], [[0, 1, 2]], {"units": "x=furlong"}, None),
    ],
)
def test_bad_records(tmp_path, header, rows, kwargs, match):
    p = _csv(tmp_path, header, rows)
    if match is None:
        with pytest.raises(ConfigError) as exc:
            mr.read_track_record(p, **kwargs)
        assert exc.value.field == "units"
    else:
        with pytest.raises(InputError, match=match):
            mr.read_track_record(p, **kwargs)


def test_a_track_is_limited_to_the_trackers_scans_and_a_record_to_its_rows(tmp_path, monkeypatch):
    """One track of MAX_SCANS + 1 scans is refused naming its last line; a record of more rows than the
    reader's limit (all tracks together; patched small here) is refused while it is read."""
    p = tmp_path / "long.csv"
    with p.open("w") as f:
        f.write("scan,x,y\n")
        f.writelines(f"{i},{i},0\n" for i in range(1, mr.MAX_SCANS + 2))
    with pytest.raises(InputError, match=rf"long.csv:{mr.MAX_SCANS + 2}: column 'scan': the record spans"):
        mr.read_track_record(p)
    import dataclasses

    monkeypatch.setattr(mr, "SPEC", dataclasses.replace(mr.SPEC, max_rows=1000))
    with pytest.raises(InputError, match=r"long.csv:1002: more than 1000 data rows"):
        mr.read_track_record(p)


# --------------------------------------------------------------------------------------------------- σ
def test_sigma_estimate_is_unbiased_on_constant_velocity_records():
    """σ̂ = 1.4826 MAD(d)/√6 on M = 400 CV records of 300 scans (σ = 50 m, 10 % of the scans missed): the mean
    over the records is within 4 standard errors (of that mean, from the records' spread) of σ. The spread
    itself is about σ/√n for n differences per axis (asymptotic 0.99 σ/√n measured for n = 48 to 2000;
    checked within 15 %). With M = 400 the test detects a relative bias of about 1.1 % or more."""
    rng = np.random.default_rng(2026)
    sigma, M, N = 50.0, 400, 300
    est, ns = [], []
    for _ in range(M):
        _, z = _cv(N, sigma, seed=int(rng.integers(2**32)), v=tuple(rng.uniform(-300, 300, 2)))
        z[rng.random(N) < 0.1] = np.nan
        e = mr.estimate_sigma(z)
        est.append(e.sigma)
        ns.append(e.n)
    est = np.array(est)
    se = est.std(ddof=1) / math.sqrt(M)
    assert abs(est.mean() - sigma) < 4 * se
    assert est.std(ddof=1) == pytest.approx(sigma / math.sqrt(np.mean(ns)), rel=0.15)


def test_sigma_estimate_is_robust_and_refuses_too_little_data():
    """1 % gross outliers (5 km; each spoils 3 second differences) leave σ̂ within 6 % of σ (mean of 50
    records; the MAD's bias with 3 % of its samples at infinity is +3.6 %), where the plain standard deviation
    of the differences is off by a factor > 5; a manoeuvre (20 m/s² for half the record) moves σ̂ by less
    than 3 %. Fewer than 10 second differences: a ConfigError on sigma."""
    rng = np.random.default_rng(7)
    robust, plain, turn = [], [], []
    for r in range(50):
        _, z = _cv(400, 50.0, seed=r)
        bad = rng.random(400) < 0.01
        zo = z + np.where(bad[:, None], 5000.0, 0.0)
        robust.append(mr.estimate_sigma(zo).sigma)
        d = zo[2:] - 2 * zo[1:-1] + zo[:-2]
        plain.append(d.std() / math.sqrt(6))
        t = np.arange(400.0)
        acc = np.where(t >= 200, 0.5 * 20.0 * (t - 200) ** 2, 0.0)
        turn.append(mr.estimate_sigma(z + np.stack([acc, 0 * acc], axis=1)).sigma)
    assert abs(np.mean(robust) / 50.0 - 1) < 0.06
    assert np.mean(plain) > 5 * 50.0
    assert abs(np.mean(turn) / 50.0 - 1) < 0.03
    few = _cv(15)[1]
    few[::3] = np.nan  # never three consecutive measured scans
    with pytest.raises(ConfigError) as exc:
        mr.estimate_sigma(few)
    assert exc.value.field == "sigma" and "give σ" in exc.value.reason
    with pytest.raises(ConfigError, match="noise-free"):
        mr.estimate_sigma(_cv(40, 0.0)[1])


def test_without_a_given_sigma_a_failed_estimate_names_the_file_not_the_option(tmp_path):
    """No --sigma and no metadata 'sigma': a record σ cannot be estimated from is the record's fault (an
    InputError naming the file, the count and the need for --sigma); asked for with --sigma estimate, the
    same failure names the option (a ConfigError on sigma)."""
    cfg = ex.TrackerConfig()
    pos, z = _cv(12)
    z[::3] = np.nan  # 8 measured scans, never three consecutive: 0 second differences
    rec = mr.read_track_record(_csv(tmp_path, ["scan", "x", "y"], [[i + 1, *r] for i, r in enumerate(z)]))
    with pytest.raises(InputError) as exc:
        rt.track_record(rec, ("cv",), cfg)
    msg = str(exc.value)
    assert msg.startswith(f"{rec.source}: σ cannot be estimated from 0 second differences (need 10")
    assert "--sigma" in msg and "Invalid value" not in msg
    with pytest.raises(ConfigError) as cexc:
        rt.track_record(rec, ("cv",), cfg, sigma="estimate")
    assert cexc.value.field == "sigma"
    assert rt.track_record(rec, ("cv",), cfg, sigma=50.0).table.meta["sigma_source"] == "--sigma"
    # 9 differences: one short of MIN_SIGMA_DIFFS (11 consecutive measured scans)
    nine = mr.read_track_record(
        _csv(
            tmp_path,
            ["t", "x", "y"],
            [[i, *r] for i, r in enumerate(_cv(11)[1])],
            name="n.csv",
        )
    )
    with pytest.raises(InputError, match=r"n.csv: σ cannot be estimated from 9 second differences \(need 10"):
        rt.track_record(nine, ("cv",), cfg)
    ten = mr.read_track_record(
        _csv(tmp_path, ["t", "x", "y"], [[i, *r] for i, r in enumerate(_cv(12)[1])], name="t.csv")
    )
    assert rt.track_record(ten, ("cv",), cfg).table.meta["sigma_differences"] == 10
    # noise-free positions: σ̂ = 0 m, outside the accepted range
    exact = mr.read_track_record(
        _csv(tmp_path, ["scan", "x", "y"], [[i + 1, *r] for i, r in enumerate(pos)], name="e.csv")
    )
    with pytest.raises(
        InputError, match=r"e.csv: σ estimated from the positions is 0 m, not in .*give σ \[m\] with --sigma"
    ):
        rt.track_record(exact, ("cv",), cfg)


def test_a_sigma_column_is_each_rows_covariance(tmp_path):
    """A user's export with a per-row 'sigma' column: each row's measurement covariance is σ² I (the trackers
    take a time-varying R); --sigma overrides it with one σ; a row with a position and no σ is refused
    naming its line. The several σ of a 'maneuver --view measurements' file are still several records."""
    cfg = ex.TrackerConfig()
    _, z = _cv(40, 30.0, seed=5)
    sig = [25 if i % 3 else 35 for i in range(40)]
    rows = [[i, *r, s] for i, (r, s) in enumerate(zip(z, sig, strict=True))]
    p = _csv(tmp_path, ["time", "x", "y", "sigma"], rows)
    rec = mr.read_track_record(p)
    np.testing.assert_allclose(rec.R[:, 0, 0], np.square(sig))
    meta = rt.track_record(rec, ("cv",), cfg).table.meta
    assert meta["sigma_source"] == "the record's covariances per row" and meta["sigma_median"] == 25.0
    given = rt.track_record(rec, ("cv",), cfg, sigma=30.0).table.meta
    assert given["sigma"] == 30.0 and given["sigma_source"] == "--sigma"
    rows[7][3] = ""
    holes = mr.read_track_record(_csv(tmp_path, ["time", "x", "y", "sigma"], rows, name="h.csv"))
    with pytest.raises(InputError, match=r"h.csv:9: the row has a position but no σ"):
        rt.track_record(holes, ("cv",), cfg)
    view = ['command: "maneuver"', 'view: "measurements"', "sigma: [100.0, 200.0]"]
    runs = [[s, 0, i + 1, *r] for s in (100.0, 200.0) for i, r in enumerate(z[:5])]
    with pytest.raises(InputError, match=r"v.csv:10: column 'sigma': several values of 'sigma' in one file"):
        mr.read_track_record(
            _csv(tmp_path, ["sigma", "run", "scan", "z_x", "z_y"], runs, meta=view, name="v.csv")
        )


# ------------------------------------------------------------------------------------------- tracking
def test_a_record_without_missed_scans_tracks_bit_identically_to_the_monte_carlo_trackers(tmp_path):
    sc = ex.ManeuverScenario("turn90", scans=240)
    z = ex.measurements(sc, 100.0, [3], 11)[0]
    p = _csv(
        tmp_path,
        ["scan", "z_x", "z_y"],
        [[i + 1, repr(float(a)), repr(float(b))] for i, (a, b) in enumerate(z)],
    )
    rec = mr.read_track_record(p)
    cfg = ex.TrackerConfig()
    out = rt.track_record(rec, ex.METHODS, cfg, sigma=100.0, consistency=None)
    cols = out.table.columns
    for m in ex.METHODS:
        ref = ex.track(m, z[None], 1.0, 100.0, cfg)
        rows = [r for r in out.table.rows if r[0] == m]
        state = np.array([[r[cols.index(c)] for c in ("x", "vx", "y", "vy", "ax", "ay")] for r in rows])
        # the per-step path (Δt = T at every step) is the fixed-period recursion to rounding
        np.testing.assert_allclose(state, ref.state[0], rtol=1e-11, atol=1e-9)
        if ref.onset is not None:
            onset = [r[cols.index("onset")] for r in rows]
            assert onset == [int(o) if o >= 0 else None for o in ref.onset[0]]
    assert out.table.meta["missed_scans"] == 0 and out.table.meta["sigma_source"] == "--sigma"


def test_the_two_point_initialisation_uses_the_first_two_measured_scans(tmp_path):
    """Noise-free CV record whose scans 1, 3 and 4 are missed: the trackers initialise on scans 2 and 5
    (velocity over 3 T) and then track the truth exactly; the output starts at scan 6."""
    pos, _ = _cv(30, T=2.0)
    rows = [[2.0 * i, *(("", "") if i in (0, 2, 3) else pos[i])] for i in range(30)]
    rec = mr.read_track_record(_csv(tmp_path, ["t", "x", "y"], rows, meta=["T: 2.0"]))
    out = rt.track_record(rec, ("imm", "cv", "glr"), ex.TrackerConfig(), sigma=30.0)
    t = out.table
    assert t.meta["init"].startswith("two-point differencing on the first two measured scans of each segment")
    assert t.meta["init"].endswith(": 2 and 5")
    cols = t.columns
    for m in ("imm", "cv", "glr"):
        rows_m = [r for r in t.rows if r[0] == m]
        assert rows_m[0][1] == 6 and len(rows_m) == 25
        xy = np.array([[r[cols.index("x")], r[cols.index("y")]] for r in rows_m])
        np.testing.assert_allclose(xy, pos[5:], rtol=0, atol=1e-6)
        assert not any(r[cols.index("declared")] for r in rows_m)


def test_imm_noises_are_a_checked_option_used_everywhere():
    assert ex.TrackerConfig().imm_q == Q_PAPER
    for bad in ((0.0, 0.001), (0.0, -1.0, 0.1), (0.0, math.nan, 0.1), (0.0, 1e7, 0.1), "abc"):
        with pytest.raises(ConfigError) as exc:
            ex.TrackerConfig(imm_q=bad)
        assert exc.value.field == "imm_q"
    sc = ex.ManeuverScenario(scans=230)
    z = ex.measurements(sc, 100.0, [0], 1)
    a = ex.track("imm", z, 1.0, 100.0, ex.TrackerConfig())
    b = ex.track("imm", z, 1.0, 100.0, ex.TrackerConfig(imm_q=(0.0, 0.001, 0.0144)))
    c = ex.track("imm", z, 1.0, 100.0, ex.TrackerConfig(imm_q=(0.0, 0.01, 1.0)))
    np.testing.assert_array_equal(a.state, b.state)
    assert not np.allclose(a.state, c.state)
    # the Monte Carlo applies it too
    cfg = ex.TrackerConfig(imm_q=(0.0, 0.01, 1.0))
    mc = ex.monte_carlo(sc, 100.0, 2, 1, ("imm",), cfg, chunk=2)["imm"]
    ref = ex.track("imm", ex.measurements(sc, 100.0, [0, 1], 1), 1.0, 100.0, cfg)
    np.testing.assert_allclose(mc.track0, ref.pos[0], rtol=1e-12)


# ------------------------------------------------------------------------------------- real records
def _geo_rows(n=80, seed=3):
    """A straight, level flight at 48° N, east at 200 m/s, reported every ~0.5 s (irregular), ISO times."""
    import pymap3d

    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.4, 0.6, n))
    lat, lon, _ = pymap3d.enu2geodetic(200.0 * t, 30.0 * t, 0.0, 48.0, 11.0, 0.0)
    stamps = [f"2026-03-01T10:00:{s:06.3f}Z" for s in t]
    return t, lat, lon, stamps


def test_a_geodetic_record_is_projected_on_its_tangent_plane_and_given_back_in_latitude_longitude(tmp_path):
    """latitude/longitude (degrees) with ISO times and --origin: the positions are pymap3d's geodetic2enu
    (1e-6 m); the output carries ISO times, the tracked latitude/longitude (noise-free: within 1e-6° of the
    input) and the frame in the metadata."""
    import pymap3d

    _, lat, lon, stamps = _geo_rows()
    p = _csv(tmp_path, ["timestamp", "latitude", "longitude"], [[s, repr(float(a)), repr(float(b))]
             for s, a, b in zip(stamps, lat, lon, strict=True)])  # fmt: skip
    rec = mr.read_track_record(p, mr.ReadOptions(origin=(48.0, 11.0, 0.0)))
    e, n, _ = pymap3d.geodetic2enu(lat, lon, 0.0, 48.0, 11.0, 0.0)
    np.testing.assert_allclose(rec.z, np.stack([e, n], axis=1), atol=1e-6)
    assert (
        rec.form == "geodetic"
        and not rec.grid
        and "tangent plane at 48.000000, 11.000000" in rec.conversion["frame"]
    )
    out = rt.track_record(rec, ("cv",), ex.TrackerConfig.tuned("aircraft"), sigma=5.0)
    c = out.table.columns
    last = out.table.rows[-1]
    assert last[c.index("time")] == stamps[-1][:-1] + "Z" or last[c.index("time")].startswith(stamps[-1][:19])
    assert (
        abs(last[c.index("latitude")] - lat[-1]) < 1e-6 and abs(last[c.index("longitude")] - lon[-1]) < 1e-6
    )


def test_nacp_gives_each_row_its_sigma(tmp_path):
    """A nacp column: σ per row = the DO-260B EPU bound / 2.4477 (NACp 9: 30 m → 12.26 m; 8: 92.6 m →
    37.83 m); NACp 0 (unknown) leaves the row without σ; a category beyond 11 is refused naming its line."""
    _, lat, lon, stamps = _geo_rows(20)
    rows = [[s, a, b, 9 if i % 2 else 8] for i, (s, a, b) in enumerate(zip(stamps, lat, lon, strict=True))]
    rec = mr.read_track_record(_csv(tmp_path, ["timestamp", "lat", "lon", "nacp"], rows))
    np.testing.assert_allclose(np.sqrt(rec.R[:4, 0, 0]), [92.6 / 2.4477, 30 / 2.4477] * 2, rtol=1e-4)
    rows[3][3] = 12
    with pytest.raises(InputError, match=r"r2.csv:5: column 'nacp': 12 is not a NACp category"):
        mr.read_track_record(_csv(tmp_path, ["timestamp", "lat", "lon", "nacp"], rows, name="r2.csv"))


def test_a_polar_record_needs_its_sensor_and_sigmas_and_matches_the_conversion(tmp_path):
    """range_nm / bearing_deg plots: refused without a sensor (naming the way to give it) and without σ's;
    with the sensor in the metadata, the positions and covariances are those of
    surveillance.local_positions.polar_to_local on the same values (ground range, no elevation: said so)."""
    from motionsig_cli.surveillance.local_positions import LocalFrame, polar_to_local

    rng = np.random.default_rng(4)
    r_nm = 20 + 0.01 * np.arange(30) + 0.001 * rng.standard_normal(30)
    b_deg = 45 + 0.05 * np.arange(30)
    rows = [
        [4.0 * i, repr(float(a)), repr(float(b))] for i, (a, b) in enumerate(zip(r_nm, b_deg, strict=True))
    ]
    bare = _csv(tmp_path, ["t", "range_nm", "bearing_deg"], rows, name="bare.csv")
    with pytest.raises(InputError, match="need the sensor's position"):
        mr.read_track_record(bare)
    with pytest.raises(InputError, match="need their σ"):
        mr.read_track_record(bare, mr.ReadOptions(sensor=(51.0, -2.0, 50.0)))
    meta = ['sensor: {"latitude": 51.0, "longitude": -2.0, "altitude_m": 50.0}', "sigma_range_nm: 0.03",
            "sigma_bearing_deg: 0.08"]  # fmt: skip
    rec = mr.read_track_record(_csv(tmp_path, ["t", "range_nm", "bearing_deg"], rows, meta=meta))
    sensor = LocalFrame(51.0, -2.0, 50.0)
    ref = polar_to_local(r_nm * 1852.0, np.radians(b_deg), sensor, sensor, sigma_range_m=0.03 * 1852.0,
                         sigma_bearing_rad=np.radians(0.08))  # fmt: skip
    np.testing.assert_allclose(rec.z, ref.position, atol=1e-9)
    np.testing.assert_allclose(rec.R, ref.covariance, rtol=1e-12)
    assert (
        rec.conversion["range_kind"] == ref.range_kind
        and rec.conversion["bearing_convention"] == "north-clockwise"
    )


def test_a_long_gap_ends_a_segment_and_each_segment_starts_afresh(tmp_path):
    """A 120 s coverage gap in a 1 s record (the default limit: max(30 s, 8 median steps)) is never
    bridged: two segments, each initialised on its own first two measurements (the output's first rows of
    segment 1 are its third measurement on), the metadata counts the gap."""
    _, z = _cv(100, 20.0, seed=9)
    t = np.concatenate([np.arange(50.0), 170.0 + np.arange(50.0)])
    rec = mr.read_track_record(_csv(tmp_path, ["t", "x", "y"], [[a, *b] for a, b in zip(t, z, strict=True)]))
    assert rec.hygiene["gaps"] == 1 and rec.segment.tolist() == [0] * 50 + [1] * 50
    out = rt.track_record(rec, ("glr",), ex.TrackerConfig(), sigma=20.0)
    c = out.table.columns
    seg1 = [r for r in out.table.rows if r[c.index("segment")] == 1]
    assert len(seg1) == 48 and seg1[0][c.index("t")] == 172.0
    assert out.table.meta["segments"] == 2 and out.table.meta["init"].endswith("1 and 2; 171 and 172")
