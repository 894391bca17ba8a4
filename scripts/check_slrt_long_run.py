"""`make reproduce`: a 10⁵-scan run (the longest `SlrtScenario` accepts) of the track-existence scores of every
fusion method (everything in the log domain: no overflow, no underflow to −inf, no NaN). One run per case, about
5 minutes each; prints the final scores."""

from __future__ import annotations

import sys
import time

import numpy as np

from motionsig_cli.existence import slrt


def main(scans: int = 100_000) -> int:
    ok = True
    for target in (True, False):
        sc = slrt.SlrtScenario(target=target, scans=scans)
        t = time.perf_counter()
        out, _ = slrt.run(sc, 1, 2008)
        finite = {m: bool(np.all(np.isfinite(v))) for m, v in out.items()}
        ok &= all(finite.values())
        final = ", ".join(f"{m} {v[0, -1]:.6g}" for m, v in out.items())
        print(
            f"target={target}: {scans} scans in {time.perf_counter() - t:.0f} s; final log LR {final}; finite {finite}"
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000))
