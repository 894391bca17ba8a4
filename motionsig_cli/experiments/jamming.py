"""ATC-10 §2 reproduced: the curves of Figs 2.1–2.16 and Tables 2.1 and 1.1 (spec ``jam-bound.md`` §5–§6).

The OCR holds no figure data, only captions: a figure preset fixes what the captions state
(quantity, K, P_DL) and assumes the rest ([A]: the P_DL set of Figs 2.1/2.2, the t set of the
(p_d, t) legends, the x ranges). Table 2.1 is the N̄_ADL = 0.01·N_T crossing of the t = 0 curves;
Table 1.1 adds the jammer's transmitter (:mod:`motionsig_cli.surveillance.antenna`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motionsig_cli import refdata
from motionsig_cli.surveillance.antenna import DEFAULT_DISH, FOOT_M, DishAntenna, jammer_antenna
from motionsig_cli.surveillance.jamming import (
    DEFAULT_SYSTEM,
    JammingDesign,
    JammingSystem,
    Quantity,
    Threshold,
    log_bound,
    log_pf,
    required_jamming,
)

LEVEL_NADL = 0.01  # Tables 1.1/2.1: N̄_ADL = 0.01·N_T, "10 % of the airborne aircraft falsely located"
T_SET = (0.0, 0.1, 0.2, 0.3, 0.5)  # [A] the (p_d, t) legends are unreadable; t = 0 is certain
PDL_SET_K1 = (0.88, 0.9, 0.99, 0.999)  # [A] Figs 2.1/2.2: the text cites 0.9, 0.999; Table 1.1 0.88
MAX_POINTS = 1_000_000  # points of one x grid
MAX_ROWS = 200_000  # rows of one curves table (designs × bounds × points), about 30 MB of CSV

# Tolerances of Table 2.1 (spec §8.1): the printed values are read off log plots to whole dB
# (±0.6 dB); K = 100 at 0.88 deviates 0.65 dB (±1 dB); K = 1000 is ill-conditioned: p_f* is within
# 6 % of its ceiling p_d, so a 13 % change in the ordinate (invisible on a log plot) moves it 1.3 dB.
TABLE_2_1_TOL_DB = {
    (10, 0.88): 0.6,
    (10, 0.999): 0.6,
    (100, 0.88): 1.0,
    (100, 0.999): 0.6,
    (1000, 0.999): 2.0,
}
TABLE_1_1_ERP_TOL_DB = {1: 1.0, 10: 0.6, 100: 0.6, 1000: 2.0}
ANTENNA_TOL = {"diameter_ft": 0.75, "beamwidth_deg": 1.0, "rf_dbw": 0.7}


@dataclass(frozen=True, slots=True)
class FigurePreset:
    """One of Figs 2.1–2.16: the captioned quantity, K and P_DL, and the assumed curve set and x range."""

    figure: str
    quantity: Quantity
    K: int
    pdl: tuple[float, ...]
    t: tuple[float, ...]
    x_range: tuple[float, float]


def _presets() -> dict[str, FigurePreset]:
    out = {
        "2.1": FigurePreset("2.1", "nfl", 1, PDL_SET_K1, (0.0,), (-22.0, -12.0)),
        "2.2": FigurePreset("2.2", "nadl", 1, PDL_SET_K1, (0.0,), (-22.0, -12.0)),
    }
    x_ranges = {10: (-20.0, 0.0), 100: (-20.0, 10.0), 1000: (-20.0, 80.0)}
    # (figure N̄_FL, figure N̄_ADL, K, P_DL); Figs 2.13/2.14 are swapped in the report (2.13 is N̄_ADL)
    pairs = [
        ("2.3", "2.4", 10, 0.88),
        ("2.5", "2.6", 10, 0.999),
        ("2.7", "2.8", 100, 0.88),
        ("2.9", "2.10", 100, 0.999),
        ("2.11", "2.12", 1000, 0.88),
        ("2.14", "2.13", 1000, 0.98),
        ("2.15", "2.16", 1000, 0.999),
    ]
    for fl, adl, K, pdl in pairs:
        out[fl] = FigurePreset(fl, "nfl", K, (pdl,), T_SET, x_ranges[K])
        out[adl] = FigurePreset(adl, "nadl", K, (pdl,), T_SET, x_ranges[K])
    return dict(sorted(out.items(), key=lambda kv: float(kv[0].split(".")[1])))


FIGURES = _presets()


def default_x_range(K: int) -> tuple[float, float]:
    """x range containing every transition for tracking length K [A] (spec §4.2)."""
    if K == 1:
        return (-22.0, -12.0)
    return (-20.0, 0.0) if K <= 10 else (-20.0, 10.0) if K <= 100 else (-20.0, 80.0)


X_LIMIT_DB = 1000.0  # |x| beyond this is physically meaningless (d = 10^(−x/20) leaves double range at ±6000)


def x_grid(x_min: float, x_max: float, step: float, *, max_points: int = MAX_POINTS) -> np.ndarray:
    """Inclusive grid from x_min to x_max in steps of ``step`` dB, values rounded to the step's decimals
    (no 0.050000000000000044); refused above ``max_points`` points or outside ±X_LIMIT_DB."""
    for name, v in (("x_min", x_min), ("x_max", x_max)):
        if not (math.isfinite(v) and abs(v) <= X_LIMIT_DB):
            raise ValueError(f"{name} must be a number within ±{X_LIMIT_DB:g} dB, got {v:g}")
    if not x_min <= x_max:
        raise ValueError(f"x_max must be >= x_min, got {x_min:g} > {x_max:g}")
    if not (math.isfinite(step) and step > 0):
        raise ValueError(f"the step must be > 0, got {step:g}")
    count = (x_max - x_min) / step
    if count + 1 > max_points:
        raise ValueError(f"{count + 1:.3g} points per curve requested; at most {max_points} here")
    n = math.floor(count + 1e-9) + 1
    decimals = max(0, 9 - math.floor(math.log10(step)))
    return np.round(x_min + step * np.arange(n), decimals)


def parse_figure(text: str) -> FigurePreset:
    """A figure name: '2.4', 'Fig. 2.4', 'fig2.4', 'Figure 2.16' (case and spaces ignored)."""
    m = re.fullmatch(r"\s*(?:fig(?:ure)?\.?\s*)?2\.0*(\d+)\s*", text, flags=re.IGNORECASE)
    preset = FIGURES.get(f"2.{int(m.group(1))}") if m else None
    if preset is None:
        raise ValueError(f"unknown figure {text!r}; one of {', '.join(FIGURES)}")
    return preset


@dataclass(frozen=True, slots=True)
class Curve:
    """One bound curve: ln N̄/N_T and ln p_f on a grid of x = 10·log10(J/P₀Bτ)."""

    quantity: Quantity
    design: JammingDesign
    pdl: float
    x_db: np.ndarray
    log_pf: np.ndarray
    log_value: np.ndarray


def designs_for(K: int, pdl: Sequence[float], t: Sequence[float]) -> list[tuple[float, JammingDesign]]:
    """One design per (P_DL, t), p_d solved from P_DL (eq 2.4.2 inverted); (target P_DL, design)."""
    return [(p, JammingDesign.from_pdl(K, p, tt)) for p in pdl for tt in t]


def curves(
    quantity: Quantity,
    designs: Sequence[tuple[float, JammingDesign]],
    x: np.ndarray,
    system: JammingSystem,
) -> list[Curve]:
    """Evaluate the bound for every design on the grid (vectorised over x)."""
    out = []
    for pdl, design in designs:
        scale = system.pf_scale(quantity, design.K)
        out.append(
            Curve(
                quantity,
                design,
                pdl,
                x,
                log_pf(x, design.p_d, scale=scale),
                log_bound(quantity, x, design, system),
            )
        )
    return out


# --- Table 2.1 ------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Table21Row:
    """One row of Table 2.1, ours beside the printed value."""

    K: int
    pdl: float
    design: JammingDesign
    threshold: Threshold
    printed_dbw: float
    relation: str  # "=" or ">" (the "> 130" entry)
    tolerance_db: float | None

    @property
    def deviation_db(self) -> float | None:
        """Ours − printed in dB (None for the "> 130" entry or an unattainable target)."""
        if self.relation != "=" or not self.threshold.attainable:
            return None
        return self.threshold.erp_dbw - self.printed_dbw

    @property
    def status(self) -> str:
        """agrees | deviates | unattainable-as-printed | unattainable | attainable-but-printed-as-bound."""
        if self.relation == ">":
            return (
                "unattainable-as-printed"
                if not self.threshold.attainable
                else "attainable-but-printed-as-bound"
            )
        if not self.threshold.attainable:
            return "unattainable"
        assert self.deviation_db is not None and self.tolerance_db is not None
        return "agrees" if abs(self.deviation_db) <= self.tolerance_db else "deviates"


def table_2_1(system: JammingSystem = DEFAULT_SYSTEM, level: float = LEVEL_NADL) -> list[Table21Row]:
    """Recompute Table 2.1: ERP at which the t = 0 N̄_ADL curve reaches ``level``·N_T."""
    printed = refdata.load("atc10_table2_1.csv")
    rows = []
    for K, pdl, erp, rel in zip(
        printed.numeric("K", integer=True),
        printed.numeric("P_DL"),
        printed.numeric("erp_dbw"),
        printed.column("relation"),
        strict=True,
    ):
        K, pdl = int(K), float(pdl)
        design = JammingDesign.from_pdl(K, pdl, 0.0, satellites=system.satellites)
        threshold = required_jamming("nadl", level, design, system)
        rows.append(Table21Row(K, pdl, design, threshold, float(erp), rel, TABLE_2_1_TOL_DB.get((K, pdl))))
    return rows


# --- Table 1.1 ------------------------------------------------------------------------------------

TABLE_1_1_PDL = (
    0.88,
    0.9,
    0.98,
    0.999,
)  # the caption's 0.88, the text's 0.9 (K = 1), and the rows' candidates


@dataclass(frozen=True, slots=True)
class Table11Row:
    """One row of Table 1.1: the printed values, the ERP for several P_DL, and the antenna chain."""

    K: int
    printed: dict[str, float]
    erp_by_pdl: dict[float, float | None]  # None: unattainable
    inverse: dict[str, float]  # from the printed ERP and rf power: gain, diameter_ft, beamwidth_deg
    forward: dict[str, float]  # from the printed ERP and diameter: gain, rf_dbw, beamwidth_deg
    tolerance_db: float
    caption_pdl: float

    @property
    def matches(self) -> list[float]:
        """The P_DL whose computed ERP lies within the row's tolerance of the printed ERP."""
        erp = self.printed["erp_dbw"]
        return [p for p, v in self.erp_by_pdl.items() if v is not None and abs(v - erp) <= self.tolerance_db]

    def flags(self) -> list[str]:
        """The report's internal inconsistencies in this row, each stated with the numbers."""
        out = []
        erp = self.printed["erp_dbw"]
        cap = self.erp_by_pdl.get(self.caption_pdl)
        if self.caption_pdl not in self.matches:
            got = "is unattainable at any jammer power" if cap is None else f"gives {cap:.2f} dBW"
            other = ", ".join(f"P_DL {p:g} gives {self.erp_by_pdl[p]:.2f}" for p in self.matches)
            out.append(
                f"caption P_DL {self.caption_pdl:g} {got}, not {erp:g}"
                + (f"; {other}" if other else "; no P_DL tried reproduces it")
            )
        for key, model in (("beamwidth_deg", self.inverse["beamwidth_deg"]),):
            if abs(model - self.printed[key]) > ANTENNA_TOL[key]:
                out.append(
                    f"beamwidth {self.printed[key]:g} deg contradicts the dish model ({model:.1f} deg)"
                )
        return out


def table_1_1(
    system: JammingSystem = DEFAULT_SYSTEM, antenna: DishAntenna = DEFAULT_DISH, level: float = LEVEL_NADL
) -> list[Table11Row]:
    """Recompute Table 1.1: the ERP at several P_DL beside the printed row, and both antenna chains."""
    printed = refdata.load("atc10_table1_1.csv")
    caption_pdl = float(printed.meta.get("caption_pdl", 0.88))
    cols = ("erp_dbw", "rf_dbw", "diameter_ft", "beamwidth_deg")
    values = {c: printed.numeric(c) for c in cols}
    rows = []
    for i, K in enumerate(printed.numeric("K", integer=True)):
        K = int(K)
        row = {c: float(values[c][i]) for c in cols}
        erp_by_pdl: dict[float, float | None] = {}
        for pdl in TABLE_1_1_PDL:
            th = required_jamming("nadl", level, JammingDesign.from_pdl(K, pdl, 0.0), system)
            erp_by_pdl[pdl] = th.erp_dbw if th.attainable else None
        inv = jammer_antenna(row["erp_dbw"], rf_dbw=row["rf_dbw"], antenna=antenna)
        fwd = jammer_antenna(row["erp_dbw"], diameter_m=row["diameter_ft"] * FOOT_M, antenna=antenna)
        rows.append(
            Table11Row(
                K,
                row,
                erp_by_pdl,
                {
                    "gain_dbi": inv.gain_dbi,
                    "diameter_ft": inv.diameter_ft,
                    "beamwidth_deg": inv.beamwidth_deg,
                },
                {"gain_dbi": fwd.gain_dbi, "rf_dbw": fwd.rf_dbw, "beamwidth_deg": fwd.beamwidth_deg},
                TABLE_1_1_ERP_TOL_DB.get(K, 1.0),
                caption_pdl,
            )
        )
    return rows


def text_anchor_k1(antenna: DishAntenna = DEFAULT_DISH) -> dict[str, float]:
    """§2.7's "33 dBW ERP … 30 watts of rf power and an antenna with a 20° beamwidth", recomputed."""
    anchor = refdata.load("atc10_table1_1.csv").meta["text_k1"]
    tx = jammer_antenna(
        float(anchor["erp_dbw"]), rf_dbw=10 * math.log10(float(anchor["rf_w"])), antenna=antenna
    )
    return {
        "printed_beamwidth_deg": float(anchor["beamwidth_deg"]),
        "beamwidth_deg": tx.beamwidth_deg,
        "gain_dbi": tx.gain_dbi,
        "diameter_ft": tx.diameter_ft,
    }
