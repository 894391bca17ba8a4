"""`make reproduce`: ATC-10 §4 (track-sat) — Tables 4.2 / 4.3, Figs 4.1–4.3 (both conventions) and the
Monte Carlo of the estimators into results/atc10_tracking/.

Each output is the CLI a user would run, its CSV beside the figure with the provenance header.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

OUT = Path("results/atc10_tracking")


def motionsig(*args: str) -> None:
    print("$ motionsig " + " ".join(args), flush=True)
    subprocess.run([sys.executable, "-m", "motionsig_cli", *args, "-q"], check=True)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    motionsig("track-sat", "table", "--which", "4.2", "-o", str(OUT / "table4_2.csv"))
    motionsig("track-sat", "table", "--which", "4.3", "-o", str(OUT / "table4_3.csv"))
    motionsig(
        "track-sat",
        "table",
        "--which",
        "4.3",
        "--params",
        "table",
        "-o",
        str(OUT / "table4_3_params_table.csv"),
    )
    for ex in ("I", "II"):
        motionsig("track-sat", "constellation", "--example", ex, "--view", "satellites", "--convention", "report",
                  "-o", str(OUT / f"constellation_{ex}.csv"))  # fmt: skip
    motionsig("track-sat", "psi", "--plot", str(OUT / "fig4_1.png"), "-o", str(OUT / "fig4_1.csv"))
    for fig in ("4.2", "4.3"):
        stem = f"fig{fig.replace('.', '_')}"
        for conv in ("corrected", "report"):
            motionsig("track-sat", "rms", "--figure", fig, "--convention", conv,
                      "--plot", str(OUT / f"{stem}_{conv}.png"), "-o", str(OUT / f"{stem}_{conv}.csv"))  # fmt: skip
    for ex, s0, rho in (("I", "50", "1"), ("II", "50", "1"), ("II", "50", "0.9"), ("I", "5", "1")):
        stem = f"montecarlo_{ex}_sigma0_{s0}_rho_{rho}"
        motionsig("track-sat", "simulate", "--example", ex, "--sigma0", s0, "--rho", rho, "--runs", "2000",
                  "--rsat-re", "9.235", "--plot", str(OUT / f"{stem}.png"), "-o", str(OUT / f"{stem}.csv"))  # fmt: skip
    print(f"results in {OUT}/")


if __name__ == "__main__":
    main()
