"""`make reproduce`: ATC-10 §2 (jam-bound) — Figs 2.1–2.16 and Tables 2.1 / 1.1 into results/atc10_jamming/.

Each figure is the CLI a user would run (`motionsig jam-bound curves --figure 2.N --plot …`), its CSV
beside it with the provenance header; both tables with the printed values, deviations and flags;
the N̄_FL curves for K > 1 also under `--convention report` (the misprinted eq 2.8.1/2.8.3 form).
"""

from __future__ import annotations

from pathlib import Path

from reproducelib import motionsig, numbered, plot_and_csv, to_csv

from motionsig_cli.atc10.jamming import FIGURES

OUT = Path("results/atc10_jamming")


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for which in ("2.1", "1.1"):
        motionsig("jam-bound", "table", "--which", which, *to_csv(OUT, numbered("table", which)))
    for name, preset in FIGURES.items():
        stem = numbered("fig", name)
        motionsig("jam-bound", "curves", "--figure", name, *plot_and_csv(OUT, stem))
        if preset.quantity == "nfl" and preset.K > 1:
            report = plot_and_csv(OUT, f"{stem}_report")
            motionsig("jam-bound", "curves", "--figure", name, "--convention", "report", *report)
    print(f"results in {OUT}/")


if __name__ == "__main__":
    main()
