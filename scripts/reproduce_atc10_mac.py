"""`make reproduce`: ATC-10 §3 (mac-roc) — Figs 3.2–3.11 and the printed numbers into results/atc10_mac/.

Each figure is the CLI a user would run, its CSV beside it with the provenance header:

* Figs 3.3–3.6: the bounds of each density with the exact ROC overlaid, and a Monte Carlo overlay
  (10⁶ trials) for ℓ = 6, 8;
* the contour table at p_d = 0.9, 0.99, 0.999 (upper bound, exact, ROC_g): the contours at fixed p_d;
* Fig. 3.8 (ROC_g), Figs 3.9–3.10 (Exp against N and Exp_g), Figs 3.2 and 3.7 (densities), Fig. 3.11
  (autocorrelations) with the Zakai bandwidths;
* importance sampling down to p_f ~ 1e-20 (ℓ = 20), the chip-level PSK ensemble (10⁷ trials) and
  the printed numbers of §3 beside ours.
"""

from __future__ import annotations

from pathlib import Path

from reproducelib import motionsig, numbered, plot_and_csv, to_csv

from motionsig_cli.atc10.mac_roc import DENSITY_OF_FIGURE

OUT = Path("results/atc10_mac")
# Fig 3.8 (ROC_g), Figs 3.9–3.10 (Exp against N and Exp_g), Figs 3.2 and 3.7 (densities)
ONE_FIGURE_COMMANDS = {
    "3.8": "gaussian",
    "3.9": "exponent",
    "3.10": "exponent",
    "3.2": "densities",
    "3.7": "densities",
}


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    motionsig("mac-roc", "report", *to_csv(OUT, "printed"))
    for fig, name in DENSITY_OF_FIGURE.items():
        stem = numbered("fig", fig)
        motionsig("mac-roc", "bounds", "--figure", fig, "--exact", *plot_and_csv(OUT, stem))
        motionsig("mac-roc", "bounds", "--figure", fig, "--lower-variant", "gallager",
                  *to_csv(OUT, f"{stem}_gallager"))  # fmt: skip
        motionsig("mac-roc", "bounds", "--density", name, "--at-pd", "0.9,0.99,0.999", "--exact",
                  *to_csv(OUT, f"{stem}_at_pd"))  # fmt: skip
        motionsig("mac-roc", "montecarlo", "--density", name, "--ell", "6,8", "--theta", "0.1:0.9:0.05", "--trials", "1e6",
                  *plot_and_csv(OUT, f"{stem}_montecarlo"))  # fmt: skip
        motionsig("mac-roc", "montecarlo", "--density", name, "--ell", "20", "--theta", "0.5,0.8", "--importance",
                  "--trials", "1e6", *to_csv(OUT, f"{stem}_importance"))  # fmt: skip
    for fig, command in ONE_FIGURE_COMMANDS.items():
        motionsig("mac-roc", command, "--figure", fig, *plot_and_csv(OUT, numbered("fig", fig)))
    motionsig("mac-roc", "bandwidth", "--curves", *plot_and_csv(OUT, "fig3_11"))
    motionsig(
        "mac-roc", "bandwidth", "--code", "barker13;mseq31;gold:45,75:3;mseq:2011", *to_csv(OUT, "bandwidth")
    )
    psk = ("mac-roc", "montecarlo", "--density", "psk")
    motionsig("mac-roc", "bounds", "--density", "psk", "--theta", "0.1:0.9:0.05", *to_csv(OUT, "psk_bounds"))
    motionsig(*psk, "--theta", "0.1:0.9:0.05", "--trials", "1e7", *plot_and_csv(OUT, "psk_montecarlo"))
    motionsig(*psk, "--code", "gold:45,75:3", "--interferers", "family",
              "--theta", "0.1:0.9:0.05", "--trials", "1e6", *to_csv(OUT, "psk_gold_family_montecarlo"))  # fmt: skip
    print(f"results in {OUT}/")


if __name__ == "__main__":
    main()
