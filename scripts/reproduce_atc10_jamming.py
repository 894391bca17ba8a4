"""`make reproduce`: ATC-10 §2 (jam-bound) — Figs 2.1–2.16 and Tables 2.1 / 1.1 into results/atc10_jamming/.

Each figure is the CLI a user would run (`motionsig jam-bound curves --figure 2.N --plot …`), its CSV
beside it with the provenance header; both tables with the printed values, deviations and flags;
the N̄_FL curves for K > 1 also under `--convention report` (the misprinted eq 2.8.1/2.8.3 form).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from motionsig_cli.experiments.jamming import FIGURES

OUT = Path("results/atc10_jamming")


def motionsig(*args: str) -> None:
    print("$ motionsig " + " ".join(args), flush=True)
    subprocess.run([sys.executable, "-m", "motionsig_cli", *args, "-q"], check=True)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    motionsig("jam-bound", "table", "--which", "2.1", "-o", str(OUT / "table2_1.csv"))
    motionsig("jam-bound", "table", "--which", "1.1", "-o", str(OUT / "table1_1.csv"))
    for name, preset in FIGURES.items():
        stem = f"fig{name.replace('.', '_')}"
        motionsig(
            "jam-bound",
            "curves",
            "--figure",
            name,
            "--plot",
            str(OUT / f"{stem}.png"),
            "-o",
            str(OUT / f"{stem}.csv"),
        )
        if preset.quantity == "nfl" and preset.K > 1:
            motionsig(
                "jam-bound",
                "curves",
                "--figure",
                name,
                "--convention",
                "report",
                "--plot",
                str(OUT / f"{stem}_report.png"),
                "-o",
                str(OUT / f"{stem}_report.csv"),
            )
    print(f"results in {OUT}/")


if __name__ == "__main__":
    main()
