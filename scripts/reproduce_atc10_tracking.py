"""`make reproduce`: ATC-10 §4 (track-sat) — Tables 4.2 / 4.3, Figs 4.1–4.3 (both conventions) and the
Monte Carlo of the estimators into results/atc10_tracking/.

Each output is the CLI a user would run, its CSV beside the figure with the provenance header.
"""

from __future__ import annotations

from pathlib import Path

from reproducelib import motionsig, numbered, plot_and_csv, to_csv

OUT = Path("results/atc10_tracking")


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for which in ("4.2", "4.3"):
        motionsig("track-sat", "table", "--which", which, *to_csv(OUT, numbered("table", which)))
    motionsig(
        "track-sat", "table", "--which", "4.3", "--params", "table", *to_csv(OUT, "table4_3_params_table")
    )
    for ex in ("I", "II"):
        motionsig("track-sat", "constellation", "--example", ex, "--view", "satellites", "--convention", "report",
                  *to_csv(OUT, f"constellation_{ex}"))  # fmt: skip
    motionsig("track-sat", "psi", *plot_and_csv(OUT, "fig4_1"))
    for fig in ("4.2", "4.3"):
        for conv in ("corrected", "report"):
            motionsig("track-sat", "rms", "--figure", fig, "--convention", conv,
                      *plot_and_csv(OUT, f"{numbered('fig', fig)}_{conv}"))  # fmt: skip
    for ex, s0, rho in (("I", "50", "1"), ("II", "50", "1"), ("II", "50", "0.9"), ("I", "5", "1")):
        stem = f"montecarlo_{ex}_sigma0_{s0}_rho_{rho}"
        motionsig("track-sat", "simulate", "--example", ex, "--sigma0", s0, "--rho", rho, "--runs", "2000",
                  "--rsat-re", "9.235", *plot_and_csv(OUT, stem))  # fmt: skip
    print(f"results in {OUT}/")


if __name__ == "__main__":
    main()
