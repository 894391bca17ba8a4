"""Write the small multilateration record of the how-to guide "Locate a transmitter from times of arrival".

    python scripts/make_howto_data.py        # writes docs/howto/data/mlat_stations.csv and mlat_toa.csv

Simulated, deterministic (``numpy.random.default_rng(4040)``): eight ground stations 6-25 km around
Frankfurt airport (50.03° N, 8.57° E), heights 80-300 m (WGS-84 latitude, longitude [deg], altitude [m]);
one aircraft at 3000 m flying east at 120 m/s for 30 s, one squitter per second. Each station's time of
arrival [s] is the emission time (the epoch's time plus a transmitter clock offset of 1 ms) plus the
geometric range over c, plus Gaussian timing noise of σ = 10 ns. Station ST3 carries a multipath error of
+400 ns (120 m) at epochs 12 to 14: the fault that the solver's chi-square test should find and exclude.
"""

from __future__ import annotations

from decimal import Decimal
from pathlib import Path

import numpy as np

from motionsig_cli.geodesy import ecef_to_geodetic, enu_to_ecef, geodetic_to_ecef

C = 299_792_458.0
OUT = Path(__file__).resolve().parents[1] / "docs" / "howto" / "data"
LAT0, LON0 = 50.03, 8.57
K, E, SIGMA_S, T0 = 8, 30, 10e-9, 1_700_000_000
FAULT_STATION, FAULT_EPOCHS, FAULT_S = 3, (12, 13, 14), 400e-9


def main() -> None:
    rng = np.random.default_rng(4040)
    r = rng.uniform(6e3, 25e3, K)
    a = np.sort(rng.uniform(0, 2 * np.pi, K))
    stations = enu_to_ecef(np.c_[r * np.cos(a), r * np.sin(a), rng.uniform(80, 300, K)], LAT0, LON0, 0.0)
    lat, lon, alt = ecef_to_geodetic(stations)
    names = [f"ST{k}" for k in range(K)]
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "mlat_stations.csv").write_text(
        "receiver,latitude,longitude,altitude\n"
        + "".join(f"{n},{la:.7f},{lo:.7f},{al:.1f}\n" for n, la, lo, al in zip(names, lat, lon, alt, strict=True))
    )
    stations = _ecef_of_written(OUT / "mlat_stations.csv")  # as written (rounded): the record agrees with the file
    t = np.arange(E, dtype=float)
    aircraft = enu_to_ecef(np.c_[-18e3 + 120.0 * t, np.full(E, 4e3), np.full(E, 3000.0)], LAT0, LON0, 0.0)
    toa = 1e-3 + np.linalg.norm(aircraft[:, None] - stations, axis=-1) / C
    toa += SIGMA_S * rng.standard_normal((E, K))
    toa[list(FAULT_EPOCHS), FAULT_STATION] += FAULT_S
    lines = ["epoch,time,receiver,toa"]
    for e in range(E):
        for k in range(K):
            lines.append(f"{e},{T0 + e},{names[k]},{Decimal(T0 + e) + Decimal(f'{toa[e, k]:.12f}')}")
    (OUT / "mlat_toa.csv").write_text("\n".join(lines) + "\n")


def _ecef_of_written(path: Path) -> np.ndarray:
    rows = np.array([line.split(",")[1:] for line in path.read_text().splitlines()[1:]], dtype=float)
    return geodetic_to_ecef(rows[:, 0], rows[:, 1], rows[:, 2])


if __name__ == "__main__":
    main()
