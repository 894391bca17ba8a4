"""Peak memory and time of ``motionsig maneuver FEED --columns track=icao24`` as the feed grows: bounded memory
for a record of many rows.

Workload: traffic's quickstart collection (``tests/data/adsb/collection_quickstart.csv.gz``, 213 aircraft,
284,505 rows), each row written ``c`` times with the aircraft renamed (``icao24`` + copy number), so that the
feed has ``c`` × 213 aircraft interleaved in time as a real feed is (every copy's rows at the same
timestamps). Each size runs as a fresh process (one worker, output to a file); the peak resident memory is
the child's ``ru_maxrss``.

What is held (the design): the file is read 200,000 rows at a time and each piece's text is dropped once
converted (:func:`motionsig_cli.records.read_record_in_pieces`); the tracks are kept as arrays; the output rows
are written to spool files as each task of whole tracks finishes and joined into ``--out`` at the end
(:func:`motionsig_cli.maneuver.record_tracking.track_records_to_files`). So memory grows only with the tracks'
arrays (bytes per row reported), not with their text or the output.

Environment: BENCH_FEED_COPIES (comma-separated copy counts; default 1,4,16: 0.28, 1.1 and 4.6 million rows;
35 gives 10^7 rows, ~1.2 GB of CSV and of output, several minutes).
"""

from __future__ import annotations

import gzip
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from benchlib import write_results

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "adsb" / "collection_quickstart.csv.gz"


def write_feed(copies: int, path: Path) -> int:
    """The collection with each row written ``copies`` times (aircraft renamed); the number of data rows."""
    with gzip.open(DATA, "rt") as f:
        header = f.readline()
        lines = f.readlines()
    with open(path, "w") as g:
        g.write(header)
        for ln in lines:
            a, b, rest = ln.split(",", 2)
            g.write("".join(f"{a},{b}{c:02d},{rest}" for c in range(copies)))
    return copies * len(lines)


def run_one(feed: Path, out: Path) -> tuple[float, float, float, str]:
    """(wall s, child CPU s, peak RSS MB, the command's summary line) of one fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "motionsig_cli", "maneuver", str(feed), "--columns", "track=icao24",
                        "--workers", "1", "-o", str(out)], capture_output=True, text=True, check=True)  # fmt: skip
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return wall, cpu, after.ru_maxrss / 1024.0, p.stderr.strip().splitlines()[-1]


def main() -> int:
    copies = [int(c) for c in os.environ.get("BENCH_FEED_COPIES", "1,4,16").split(",")]
    rows_out = []
    with tempfile.TemporaryDirectory(prefix="bench-feed-") as d:
        for c in sorted(copies):  # ru_maxrss of children is the largest so far: smallest first
            feed, out = Path(d) / f"feed{c}.csv", Path(d) / f"out{c}.csv"
            n = write_feed(c, feed)
            wall, cpu, rss, note = run_one(feed, out)
            mb_in, mb_out = feed.stat().st_size / 1e6, out.stat().st_size / 1e6
            print(f"{n:>10,} rows ({c * 213} aircraft): {wall:6.1f} s wall, {cpu:6.1f} s CPU, peak {rss:7.0f} MB "
                  f"({rss * 1e6 / n:5.0f} B/row); in {mb_in:.0f} MB, out {mb_out:.0f} MB")  # fmt: skip
            rows_out.append({"case": f"maneuver FEED, {n} rows, {c * 213} aircraft", "seconds": cpu, "units": n,
                             "unit": "row", "how": f"fresh process, 1 worker, CPU time (wall {wall:.1f} s); peak RSS "
                             f"{rss:.0f} MB ({rss * 1e6 / n:.0f} B/row); CSV in {mb_in:.0f} MB, out {mb_out:.0f} MB; "
                             f"{note}"})  # fmt: skip
            feed.unlink()
            out.unlink()
    path = write_results(
        "bench_feed_memory",
        [
            "peak resident memory of maneuver on a feed of n rows (the collection's rows repeated under new icao24s)",
            "each size a fresh process; ru_maxrss of the child",
        ],
        rows_out,
    )
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
