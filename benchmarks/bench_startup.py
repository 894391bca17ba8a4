"""Start-up time of the command line: ``motionsig --help``, a small command and a table command, beside
``python -c "import numpy, typer"`` measured in the same run (the floor any typer + NumPy tool pays).

Each case is a fresh process, run 10 times interleaved with the others (so a slow moment of the machine
hits every case alike); the median is reported, with the fastest and slowest run. Every stage of a pipe
(``motionsig encode gps | motionsig encode correlations -``) pays the start-up once.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from benchlib import write_results

REPEATS = 10
CASES = {
    'python -c "import numpy, typer"': [sys.executable, "-c", "import numpy, typer"],
    "motionsig --help": [sys.executable, "-m", "motionsig_cli", "--help"],
    "motionsig encode gps --prn 1": [sys.executable, "-m", "motionsig_cli", "encode", "gps", "--prn", "1"],
    "motionsig jam-bound table": [sys.executable, "-m", "motionsig_cli", "jam-bound", "table"],
}
TARGETS = {"motionsig --help": 0.3, "motionsig encode gps --prn 1": 0.4, "motionsig jam-bound table": 0.8}


def main() -> int:
    times: dict[str, list[float]] = {name: [] for name in CASES}
    for argv in CASES.values():  # warm the file cache and the byte-code once
        subprocess.run(argv, capture_output=True, check=True)
    for _ in range(REPEATS):
        for name, argv in CASES.items():
            t0 = time.perf_counter()
            subprocess.run(argv, capture_output=True, check=True)
            times[name].append(time.perf_counter() - t0)
    rows = []
    for name, ts in times.items():
        med = statistics.median(ts)
        target = TARGETS.get(name)
        how = f"median of {REPEATS} fresh processes (min {min(ts):.3f} s, max {max(ts):.3f} s)"
        if target is not None:
            how += f"; goal <= {target} s on 2 cores"
        rows.append({"case": name, "seconds": med, "units": 1, "unit": "process", "how": how})
        print(f"{name:40s} {med:.3f} s  (min {min(ts):.3f}, max {max(ts):.3f})")
    path = write_results(
        "bench_startup",
        [
            "start-up: wall time of a fresh process, from exec to exit, output discarded",
            f"each case {REPEATS} times, interleaved; median (min, max in 'how')",
        ],
        rows,
    )
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
