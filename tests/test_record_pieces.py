"""Reading a record in pieces (tables.iter_table, records.read_record_in_pieces): the same values, to the bit,
as reading it whole, with errors naming the file's own line wherever the piece boundaries fall."""

from __future__ import annotations

import gzip
import shutil

import numpy as np
import pytest

from motionsig_cli.errors import InputError
from motionsig_cli.maneuver import record as mr
from motionsig_cli.records import read_record, read_record_in_pieces
from motionsig_cli.tables import iter_table, read_table
from tests.adsb import ADSB_DIR

COLLECTION = ADSB_DIR / "collection_quickstart.csv.gz"


def _equal_records(a, b) -> None:
    assert a.values.keys() == b.values.keys()
    for k in a.values:
        assert a.values[k].dtype == b.values[k].dtype, k
        if a.values[k].dtype == object:
            assert a.values[k].tolist() == b.values[k].tolist(), k
        else:
            np.testing.assert_array_equal(a.values[k], b.values[k], err_msg=k)  # bit for bit (NaN where NaN)
    np.testing.assert_array_equal(a.lines, b.lines)
    assert (a.columns, a.units, a.time_origin, a.extra, a.meta, a.source, a.header_line) == (
        b.columns, b.units, b.time_origin, b.extra, b.meta, b.source, b.header_line)  # fmt: skip


@pytest.mark.parametrize("chunk", [1, 997, 40_000])
def test_a_real_collection_in_pieces_equals_it_read_whole(chunk, tmp_path):
    """ISO timestamps (each piece's counted from the file's first, as whole), labels, units in the header;
    gzip read through; chunk 1: every row its own piece."""
    src = tmp_path / "c.csv.gz"
    if chunk == 1:  # the first 3,000 rows only: a piece per row is slow
        with gzip.open(COLLECTION, "rt") as f, gzip.open(src, "wt") as g:
            for _ in range(3001):
                g.write(f.readline())
    else:
        shutil.copy(COLLECTION, src)
    whole = read_record(read_table(src, max_rows=mr.MAX_ROWS), mr.SPEC, columns="track=icao24")
    pieces = read_record_in_pieces(src, mr.SPEC, columns="track=icao24", chunk_rows=chunk)
    _equal_records(whole, pieces)
    assert whole.time_origin is not None and pieces.values["time"][-1] > 300.0
    labels = pieces.values["track"]
    assert len({id(v) for v in labels.tolist()}) == len(set(labels.tolist()))  # a label's repeats share one str


def test_the_tracks_of_a_file_read_in_pieces_equal_those_of_its_table(tmp_path, monkeypatch):
    """read_track_records of a path (in pieces) and of the same file's table (whole) give the same tracks."""
    monkeypatch.setattr("motionsig_cli.records.CHUNK_ROWS", 5_000)
    a = mr.read_track_records(COLLECTION, columns="track=icao24")
    b = mr.read_track_records(read_table(COLLECTION, max_rows=mr.MAX_ROWS), columns="track=icao24")
    assert [r.label for r in a.tracks] == [r.label for r in b.tracks] and len(a.tracks) == 213
    for ra, rb in zip(a.tracks, b.tracks, strict=True):
        for k in ("z", "t", "scan", "segment", "measured"):
            np.testing.assert_array_equal(getattr(ra, k), getattr(rb, k), err_msg=f"{ra.label} {k}")


def _numeric_file(path, n=2500, bad_at=None, comment_at=None, run_change_at=None):
    lines = ["# units: {\"x\": \"km\"}", "t,x,y,run"]
    for i in range(n):
        if comment_at is not None and i == comment_at:
            lines.append("# sigma: 99")  # after the header: a comment, not metadata
        x = "oops" if i == bad_at else f"{0.01 * i:.3f}"
        lines.append(f"{i * 0.5},{x},{2 * i},{2 if run_change_at is not None and i >= run_change_at else 1}")
    path.write_text("\n".join(lines) + "\n")
    return path


def test_errors_name_the_files_line_in_a_later_piece(tmp_path):
    """A bad cell in the third piece: its line in the file (two header lines, one per row before it)."""
    f = _numeric_file(tmp_path / "r.csv", bad_at=2345)
    with pytest.raises(InputError, match=r"r\.csv:2348: column 'x'"):
        read_record_in_pieces(f, mr.SPEC, chunk_rows=1000)
    g = _numeric_file(tmp_path / "s.csv", run_change_at=1500)  # a second run starts in the second piece
    with pytest.raises(InputError, match=r"s\.csv:1503: column 'run': several values of 'run'"):
        mr.read_track_records(g, mr.ReadOptions())


def test_comments_after_the_header_are_not_metadata_in_any_piece(tmp_path):
    f = _numeric_file(tmp_path / "r.csv", comment_at=1800)
    rec = read_record_in_pieces(f, mr.SPEC, chunk_rows=700)
    assert "sigma" not in rec.meta and rec.meta["units"] == {"x": "km"}
    assert rec.values["x"][1000] == pytest.approx(10_000.0)  # km from the metadata, in every piece
    whole = read_record(read_table(f), mr.SPEC)
    _equal_records(whole, rec)


def test_iter_table_pieces_and_limits(tmp_path):
    f = _numeric_file(tmp_path / "r.csv", n=10)
    pieces = list(iter_table(f, chunk_rows=4))
    assert [len(p.rows) for p in pieces] == [4, 4, 2]
    assert [p.lines for p in pieces] == [(3, 4, 5, 6), (7, 8, 9, 10), (11, 12)]
    assert [row for p in pieces for row in p.rows] == read_table(f).rows
    header_only = tmp_path / "h.csv"
    header_only.write_text("t,x\n")
    assert [len(p.rows) for p in iter_table(header_only, chunk_rows=4)] == [0]
    with pytest.raises(InputError, match=r"r\.csv:11: more than 8 data rows"):
        list(iter_table(f, chunk_rows=4, max_rows=8))
    with pytest.raises(ValueError, match="chunk_rows"):
        list(iter_table(f, chunk_rows=0))


def test_parquet_in_batches_equals_it_read_whole(tmp_path):
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    t = read_table(COLLECTION, max_rows=mr.MAX_ROWS)
    n = 5000
    cols = {c: [row[j] for row in t.rows[:n]] for j, c in enumerate(t.columns)}
    pq.write_table(pa.table(cols), tmp_path / "c.parquet", row_group_size=1200)
    whole = read_table(tmp_path / "c.parquet")
    pieces = list(iter_table(tmp_path / "c.parquet", chunk_rows=999))
    assert [row for p in pieces for row in p.rows] == whole.rows and len(whole.rows) == n
    assert tuple(line for p in pieces for line in p.lines) == whole.lines == tuple(range(2, n + 2))
