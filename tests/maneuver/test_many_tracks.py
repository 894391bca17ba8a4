"""Many tracks in one record (maneuver.record.read_track_records, record_tracking.track_records): a track
column (icao24, track_id, …), rows interleaved in time, each track cleaned and segmented on its own, all
segments tracked in one batched call.

Oracles: each track tracked alone (the single-track path, itself tested against the Monte Carlo trackers
and FilterPy) must give the same rows; a real collection of 213 aircraft (tests/data/adsb, traffic's
quickstart sample, MIT) as recorded, gzip-compressed."""

import gzip
import math

import numpy as np
import pytest

from motionsig_cli.errors import InputError
from motionsig_cli.maneuver import record as mr
from motionsig_cli.maneuver import record_tracking as rt
from motionsig_cli.maneuver.study import TrackerConfig
from motionsig_cli.tables import Table, format_csv, read_table
from tests.adsb import ADSB_DIR
from tests.cli.helpers import run


def _interleaved(n_tracks=6, seed=1):
    """n tracks at irregular times, interleaved in one table (one too short to track)."""
    rng = np.random.default_rng(seed)
    rows, truth = [], {}
    for k in range(n_tracks):
        n = 2 if k == n_tracks - 1 else int(rng.integers(80, 200))
        t = 100.0 * k + np.cumsum(rng.uniform(0.4, 1.6, n))
        v = rng.uniform(-250, 250, 2)
        z = np.stack([v[0] * t, v[1] * t], axis=1) + 1000.0 * k + 10.0 * rng.standard_normal((n, 2))
        truth[f"ac{k}"] = (t, z)
        rows += [(f"ac{k}", float(a), float(b), float(c)) for a, (b, c) in zip(t, z, strict=True)]
    rows.sort(key=lambda r: r[1])
    return Table(columns=("icao24", "time", "x", "y"), rows=rows), truth


@pytest.mark.parametrize("method", ["imm", "glr", "mlr", "cv"])
def test_many_tracks_in_one_call_equal_each_track_alone(method):
    """Each track's rows of the batched call equal that track tracked alone (to rounding: the batch runs
    every segment with its own Δt); the track too short to initialise is listed, not an error."""
    table, _ = _interleaved()
    cfg = TrackerConfig.tuned("aircraft")
    ts = mr.read_track_records(table)
    assert [r.label for r in ts.tracks] == [f"ac{k}" for k in range(5)]
    assert ts.untracked[0][0] == "ac5" and "need at least 3" in ts.untracked[0][1]
    both = rt.track_records(ts, (method,), cfg, sigma=10.0)
    c = both.table.columns
    assert c[0] == "track" and both.table.meta["tracks"] == 5
    for rec in ts.tracks:
        alone = rt.track_record(rec, (method,), cfg, sigma=10.0)
        mine = [r for r in both.table.rows if r[0] == rec.label]
        assert len(mine) == len(alone.table.rows)
        a = np.array([r[c.index("x") : c.index("ay") + 1] for r in mine], float)
        ca = alone.table.columns
        b = np.array([r[ca.index("x") : ca.index("ay") + 1] for r in alone.table.rows], float)
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-6)


def test_one_track_function_refuses_a_record_of_many():
    table, _ = _interleaved(3)
    with pytest.raises(InputError, match=r"column 'icao24': the record holds 3 tracks"):
        mr.read_track_record(table)


def test_a_label_column_with_a_unit_is_not_the_track(tmp_path):
    """ADS-B exports name the course 'track [deg]': a label role never takes a column with a unit."""
    p = tmp_path / "r.csv"
    p.write_text("time,track [deg],x,y\n" + "".join(f"{i},{90 + i},{100.0 * i},{3.0 * i * i}\n" for i in range(12)))
    rec = mr.read_track_record(p, columns=None)
    assert rec.label == "" and "track" not in rec.record.columns


def test_gzip_records_are_read_by_their_content_and_bounded(tmp_path):
    """A .csv.gz is read through its decompression (by its magic bytes); a corrupt one, or one that inflates
    past the byte limit, is one error naming the file."""
    text = "t,x,y\n" + "".join(f"{i},{10.0 * i},{5.0 * i}\n" for i in range(50))
    p = tmp_path / "r.csv.gz"
    p.write_bytes(gzip.compress(text.encode()))
    assert len(read_table(p).rows) == 50
    bad = tmp_path / "bad.csv.gz"
    bad.write_bytes(gzip.compress(text.encode())[:-12])
    with pytest.raises(InputError, match=r"bad.csv.gz: not a readable gzip file"):
        read_table(bad)
    bomb = tmp_path / "bomb.gz"
    bomb.write_bytes(gzip.compress(b"t,x,y\n" + b"1,2,3\n" * 200_000))
    with pytest.raises(InputError, match=r"bomb.gz: larger than 100000 bytes"):
        read_table(bomb, max_bytes=100_000)


@pytest.mark.slow
def test_a_real_collection_of_hundreds_of_aircraft_in_one_call(capsys, tmp_path):
    """traffic's quickstart collection as recorded (284,505 rows, 213 aircraft interleaved in time, ISO
    times, icao24, latitude, longitude, altitude in ft; gzip CSV): one call, exit 0, every aircraft with
    enough reports in the output (the others listed in the metadata), no speed above 600 m/s."""
    out_file = tmp_path / "out.csv"
    rc, _, err = run(capsys, "maneuver", str(ADSB_DIR / "collection_quickstart.csv.gz"), "--method", "imm",
                     "-o", str(out_file))  # fmt: skip
    assert rc == 0, err
    t = read_table(out_file, max_rows=10**7, max_bytes=2**31)
    c = t.columns
    tracked = {r[0] for r in t.rows}
    assert len(tracked) + len(t.meta["untracked_tracks"]) == 213 and len(tracked) >= 200
    v = np.array([[float(r[c.index("vx")]), float(r[c.index("vy")])] for r in t.rows])
    assert np.hypot(v[:, 0], v[:, 1]).max() <= 600.0


def test_parquet_records_read_as_their_csv_twins(tmp_path):
    """A Parquet export (timestamps as UTC timestamps, nulls) gives the same tracks as the same rows in CSV;
    a damaged Parquet file and one with too many rows are one error naming the file."""
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    table, _ = _interleaved(4, seed=3)
    rows = table.rows
    t0 = np.datetime64("2026-03-01T10:00:00.000")
    stamps = [t0 + np.timedelta64(round(r[1] * 1000), "ms") for r in rows]
    xs = [None if i == 7 else r[2] for i, r in enumerate(rows)]
    pq.write_table(
        pa.table({"timestamp": pa.array(np.array(stamps).astype("int64"), pa.int64()).cast(pa.timestamp("ms", tz="UTC")), "icao24": [r[0] for r in rows],
                  "x": xs, "y": [r[3] for r in rows]}),
        tmp_path / "r.parquet",
    )  # fmt: skip
    csv_rows = [(str(np.datetime_as_string(s, unit="ms")) + "Z", r[0], "" if x is None else repr(x), repr(r[3]))
                for s, r, x in zip(stamps, rows, xs, strict=True)]  # fmt: skip
    (tmp_path / "r.csv").write_text("timestamp,icao24,x,y\n" + "".join(",".join(c) + "\n" for c in csv_rows))
    cfg = TrackerConfig.tuned("aircraft")
    a = rt.track_records(mr.read_track_records(tmp_path / "r.parquet"), ("glr",), cfg, sigma=10.0).table
    b = rt.track_records(mr.read_track_records(tmp_path / "r.csv"), ("glr",), cfg, sigma=10.0).table
    assert a.rows == b.rows and a.columns == b.columns
    bad = tmp_path / "bad.parquet"
    bad.write_bytes(b"PAR1" + b"\0" * 100)
    with pytest.raises(InputError, match=r"bad.parquet: not a readable Parquet file"):
        read_table(bad)
    with pytest.raises(InputError, match=r"r.parquet: more than 10 data rows"):
        read_table(tmp_path / "r.parquet", max_rows=10)


def test_the_engine_gives_the_same_bytes_for_any_workers_and_resumes(capsys, tmp_path, monkeypatch, dask_address):
    """A many-track record on the engine (tasks of whole tracks; small tasks here so there are several):
    the same tables as all segments in one batch (to rounding: a batch's composition moves the last digit of
    a few values) and as track_records (exactly: it runs the same tasks); through the command, 1 worker, 2
    workers, a Dask cluster and a run resumed from its checkpoint write the same bytes."""
    from motionsig_cli.engine import Engine, run_job

    monkeypatch.setattr(rt, "TASK_STEPS", 150)
    table, _ = _interleaved(6, seed=5)
    ts = mr.read_track_records(table)
    cfg = TrackerConfig.tuned("aircraft")
    plan = rt.plan_tracking(ts, ("imm", "glr"), cfg)
    job = rt.RecordJob(plan)
    assert len(job.tasks()) >= 3
    got = run_job(job, Engine(workers=1))
    same = rt.track_records(ts, ("imm", "glr"), cfg)
    assert got.table.rows == same.table.rows and got.events.rows == same.events.rows
    one = plan.tables(plan.track(range(len(plan.segs))))  # every segment in one batch
    c = one.table.columns
    num = [c.index(k) for k in ("x", "vx", "y", "vy", "ax", "ay", "nis")]
    a = np.array([[np.nan if r[j] is None else r[j] for j in num] for r in one.table.rows], float)
    b = np.array([[np.nan if r[j] is None else r[j] for j in num] for r in got.table.rows], float)
    np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-9)
    p = tmp_path / "feed.csv"
    p.write_text("icao24,time,x,y\n" + "".join(",".join(repr(v) if isinstance(v, float) else v for v in r) + "\n"
                                            for r in table.rows))  # fmt: skip
    outs = []
    for args in ((), ("--workers", "2"), ("--scheduler", dask_address), ("--checkpoint", str(tmp_path / "ck")),
                 ("--checkpoint", str(tmp_path / "ck"))):  # fmt: skip
        o = tmp_path / f"o{len(outs)}.csv"
        rc, _, err = run(capsys, "maneuver", str(p), "--method", "imm,glr", "-o", str(o), *args)
        assert rc == 0, err
        outs.append(o.read_bytes())
    assert all(o == outs[0] for o in outs)
    # the command writes its rows to files as tasks finish and joins them: the bytes of the table in memory
    mem = rt.track_records(mr.read_track_records(p), ("imm", "glr"), cfg)
    assert outs[0] == format_csv(mem.table).encode()
    assert outs[0].count(b"\n") > len(mem.table.rows) > 500


def test_batches_are_the_least_cost_cut_of_the_sorted_segments():
    """_buckets against brute force: every cut of up to 9 sorted segments into batches of at most `size`,
    the modelled cost Σ L_longest (STEP_COST_LANES + |batch|) (its docstring) least."""
    import itertools

    rng = np.random.default_rng(3)
    for _ in range(40):
        S, size = int(rng.integers(1, 10)), int(rng.integers(1, 5))
        lengths = sorted(rng.integers(1, 3000, S).tolist(), reverse=True)
        order = list(range(100, 100 + S))

        def cost(batches, lengths=lengths):
            return sum(lengths[b[0] - 100] * (rt.STEP_COST_LANES + len(b)) for b in batches)

        best = math.inf
        for cuts in itertools.product((0, 1), repeat=S - 1):
            bounds = [0, *[k + 1 for k, c in enumerate(cuts) if c], S]
            batches = [order[a:b] for a, b in itertools.pairwise(bounds)]
            if all(len(b) <= size for b in batches):
                best = min(best, cost(batches))
        got = rt._buckets(order, lengths, size)
        assert [i for b in got for i in b] == order and all(len(b) <= size for b in got)
        assert cost(got) == pytest.approx(best, rel=1e-12)
