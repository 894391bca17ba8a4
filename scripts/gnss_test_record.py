"""Make ``tests/data/gnss/gsdc2022_mtv.csv`` and ``gsdc2022_mtv_truth.csv`` from gnss_lib_py's copy of a
Google Smartphone Decimeter Challenge 2022 trace (a phone standing still in Mountain View, 2021-04-29).

Usage: ``python scripts/gnss_test_record.py DEVICE_GNSS_CSV GROUND_TRUTH_CSV OUT_DIR``, with the files
``data/unit_test/google_decimeter_2022/device_gnss.csv`` and ``ground_truth.csv`` of
Stanford-NavLab/gnss_lib_py (tests/data/gnss/README.md names the commit).

Kept: the GPS L1 rows (one signal per satellite). Per row: the epoch (the file's ``utcTimeMillis`` in
order), the time [s] since the first epoch, the satellite ``G<svid>``, its ECEF position at the signal's
transmission (``SvPosition{X,Y,Z}EcefMeters``: not rotated for the flight time), and

    pseudorange = RawPseudorangeMeters + SvClockBiasMeters − IsrbMeters − IonosphericDelayMeters
                  − TroposphericDelayMeters   [m]

(satellite clock, inter-signal bias, ionosphere and troposphere corrected with the values the data set
gives), ``sigma`` = RawPseudorangeUncertaintyMeters [m], and the corrections themselves (``sat_clock_m``,
``iono_m``, ``tropo_m``). The truth file has, per epoch, the ground truth (latitude, longitude, height
above the WGS-84 ellipsoid) at the epoch's time and the data set's own weighted least-squares position
(``wls_x``, ``wls_y``, ``wls_z``, ECEF [m]; all its constellations).
"""

from __future__ import annotations

import csv
import sys
from decimal import Decimal
from pathlib import Path


def main(device: str, truth: str, out_dir: str) -> None:
    rows = [r for r in csv.DictReader(open(device, newline="")) if r["SignalType"] == "GPS_L1"]
    millis = sorted({int(r["utcTimeMillis"]) for r in rows})
    out = Path(out_dir)
    with open(out / "gsdc2022_mtv.csv", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["epoch", "time", "satellite", "x", "y", "z", "pseudorange", "sigma",
                    "sat_clock_m", "iono_m", "tropo_m"])  # fmt: skip
        for r in sorted(rows, key=lambda r: (int(r["utcTimeMillis"]), int(r["Svid"]))):
            ms = int(r["utcTimeMillis"])
            pr = (Decimal(r["RawPseudorangeMeters"]) + Decimal(r["SvClockBiasMeters"]) - Decimal(r["IsrbMeters"])
                  - Decimal(r["IonosphericDelayMeters"]) - Decimal(r["TroposphericDelayMeters"]))  # fmt: skip
            w.writerow([millis.index(ms), str(Decimal(ms - millis[0]) / 1000), f"G{int(r['Svid']):02d}",
                        *(r[f"SvPosition{a}EcefMeters"] for a in "XYZ"), f"{pr:.6f}",
                        r["RawPseudorangeUncertaintyMeters"], r["SvClockBiasMeters"],
                        r["IonosphericDelayMeters"], r["TroposphericDelayMeters"]])  # fmt: skip
    gt = {int(r["UnixTimeMillis"]): r for r in csv.DictReader(open(truth, newline=""))}
    wls = {int(r["utcTimeMillis"]): r for r in rows}
    with open(out / "gsdc2022_mtv_truth.csv", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["epoch", "latitude", "longitude", "altitude", "wls_x", "wls_y", "wls_z"])
        for e, ms in enumerate(millis):
            g = gt[ms]
            w.writerow([e, g["LatitudeDegrees"], g["LongitudeDegrees"], g["AltitudeMeters"],
                        *(wls[ms][f"WlsPosition{a}EcefMeters"] for a in "XYZ")])  # fmt: skip


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
