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

import subprocess
import sys
from pathlib import Path

from motionsig_cli.experiments.mac_roc import DENSITY_OF_FIGURE

OUT = Path("results/atc10_mac")


def motionsig(*args: str) -> None:
    print("$ motionsig " + " ".join(args), flush=True)
    subprocess.run([sys.executable, "-m", "motionsig_cli", *args, "-q"], check=True)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    motionsig("mac-roc", "report", "-o", str(OUT / "printed.csv"))
    for fig, name in DENSITY_OF_FIGURE.items():
        stem = f"fig{fig.replace('.', '_')}"
        motionsig(
            "mac-roc",
            "bounds",
            "--figure",
            fig,
            "--exact",
            "--plot",
            str(OUT / f"{stem}.png"),
            "-o",
            str(OUT / f"{stem}.csv"),
        )
        motionsig(
            "mac-roc",
            "bounds",
            "--figure",
            fig,
            "--lower-variant",
            "gallager",
            "-o",
            str(OUT / f"{stem}_gallager.csv"),
        )
        motionsig(
            "mac-roc",
            "bounds",
            "--density",
            name,
            "--at-pd",
            "0.9,0.99,0.999",
            "--exact",
            "-o",
            str(OUT / f"{stem}_at_pd.csv"),
        )
        motionsig("mac-roc", "montecarlo", "--density", name, "--ell", "6,8", "--theta", "0.1:0.9:0.05", "--trials", "1e6",
                  "--plot", str(OUT / f"{stem}_montecarlo.png"), "-o", str(OUT / f"{stem}_montecarlo.csv"))  # fmt: skip
        motionsig("mac-roc", "montecarlo", "--density", name, "--ell", "20", "--theta", "0.5,0.8", "--importance",
                  "--trials", "1e6", "-o", str(OUT / f"{stem}_importance.csv"))  # fmt: skip
    motionsig(
        "mac-roc",
        "gaussian",
        "--figure",
        "3.8",
        "--plot",
        str(OUT / "fig3_8.png"),
        "-o",
        str(OUT / "fig3_8.csv"),
    )
    for fig in ("3.9", "3.10"):
        stem = f"fig{fig.replace('.', '_')}"
        motionsig(
            "mac-roc",
            "exponent",
            "--figure",
            fig,
            "--plot",
            str(OUT / f"{stem}.png"),
            "-o",
            str(OUT / f"{stem}.csv"),
        )
    for fig in ("3.2", "3.7"):
        stem = f"fig{fig.replace('.', '_')}"
        motionsig(
            "mac-roc",
            "densities",
            "--figure",
            fig,
            "--plot",
            str(OUT / f"{stem}.png"),
            "-o",
            str(OUT / f"{stem}.csv"),
        )
    motionsig(
        "mac-roc", "bandwidth", "--curves", "--plot", str(OUT / "fig3_11.png"), "-o", str(OUT / "fig3_11.csv")
    )
    motionsig(
        "mac-roc",
        "bandwidth",
        "--code",
        "barker13;mseq31;gold:45,75:3;mseq:2011",
        "-o",
        str(OUT / "bandwidth.csv"),
    )
    motionsig(
        "mac-roc", "bounds", "--density", "psk", "--theta", "0.1:0.9:0.05", "-o", str(OUT / "psk_bounds.csv")
    )
    motionsig("mac-roc", "montecarlo", "--density", "psk", "--theta", "0.1:0.9:0.05", "--trials", "1e7",
              "--plot", str(OUT / "psk_montecarlo.png"), "-o", str(OUT / "psk_montecarlo.csv"))  # fmt: skip
    motionsig("mac-roc", "montecarlo", "--density", "psk", "--code", "gold:45,75:3", "--interferers", "family",
              "--theta", "0.1:0.9:0.05", "--trials", "1e6", "-o", str(OUT / "psk_gold_family_montecarlo.csv"))  # fmt: skip
    print(f"results in {OUT}/")


if __name__ == "__main__":
    main()
