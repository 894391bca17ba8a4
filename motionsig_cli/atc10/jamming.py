"""Section 2 of ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972) reproduced: the
curves of Figs 2.1–2.16, Tables 2.1 and 1.1, and the tables of the ``jam-bound`` commands.

The report's scanned figures carry no readable data, only captions: a figure preset fixes what the
captions state (quantity, K, P_DL) and assumes the rest ([A]: the P_DL set of Figs 2.1/2.2, the t set
of the (p_d, t) legends, the x ranges). Table 2.1 is the N̄_ADL = 0.01·N_T crossing of the t = 0
curves; Table 1.1 adds the jammer's transmitter (:mod:`motionsig_cli.surveillance.antenna`).

Each command has one function here that returns its table (rows, columns and provenance) and summary:
:func:`curves_table` (with the figure's panels), :func:`threshold_table`, :func:`report_table`,
:func:`design_table` and :func:`antenna_table`. Their configurations check every field and raise
:class:`~motionsig_cli.config.ConfigError` naming it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from motionsig_cli import refdata
from motionsig_cli.config import ConfigError, in_range, one_of, positive
from motionsig_cli.surveillance.antenna import DEFAULT_DISH, FOOT_M, DishAntenna, jammer_antenna
from motionsig_cli.surveillance.jamming import (
    DEFAULT_SYSTEM,
    JammingDesign,
    JammingSystem,
    Quantity,
    Threshold,
    check_level,
    log_bound,
    log_pf,
    required_jamming,
    t_for,
)
from motionsig_cli.tables import Table, make_meta

LEVEL_NADL = 0.01  # Tables 1.1/2.1: N̄_ADL = 0.01·N_T, "10 % of the airborne aircraft falsely located"
T_SET = (0.0, 0.1, 0.2, 0.3, 0.5)  # [A] the (p_d, t) legends are unreadable; t = 0 is certain
PDL_SET_K1 = (0.88, 0.9, 0.99, 0.999)  # [A] Figs 2.1/2.2: the text cites 0.9, 0.999; Table 1.1 0.88
MAX_POINTS = 1_000_000  # points of one x grid
MAX_ROWS = 200_000  # rows of one curves table (designs × bounds × points), about 30 MB of CSV

# Tolerances of Table 2.1: the printed values are read off log plots to whole dB. A row's tolerance is
# ±0.5 dB (whole dB) plus S·ε, S = d ERP / d log10(N̄_ADL/N_T) at the crossing and ε the reading error of
# the log ordinate. S = 1.55, 1.06, 1.72 dB per decade for K = 10 (0.88, 0.999) and K = 100 (0.999):
# their ±0.6 dB allows ε = 0.1/1.72 = 0.058 decade (14 %) at the steepest of them. K = 100 at 0.88 is
# worse conditioned (S = 3.00: p_f*/p_d = 0.52, the curve flatter at the crossing), so the same ε gives
# ±(0.5 + 3.00·0.058) = ±0.67 dB; it deviates 0.65 dB (printed 56 needs the ordinate read ≥ 11.8 % high).
# K = 1000 is ill-conditioned: p_f* is within 6 % of its ceiling p_d (S = 22 dB per decade), so a 13 %
# change in the ordinate (invisible on a log plot) moves it 1.3 dB.
TABLE_2_1_TOL_DB = {
    (10, 0.88): 0.6,
    (10, 0.999): 0.6,
    (100, 0.88): 0.67,
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
    """x range containing every transition for tracking length K [A: our choice; the figures' axes are
    unreadable]."""
    if K == 1:
        return (-22.0, -12.0)
    return (-20.0, 0.0) if K <= 10 else (-20.0, 10.0) if K <= 100 else (-20.0, 80.0)


X_LIMIT_DB = 1000.0  # |x| beyond this is physically meaningless (d = 10^(−x/20) leaves double range at ±6000)


def x_grid(x_min: float, x_max: float, step: float, *, max_points: int = MAX_POINTS) -> np.ndarray:
    """Inclusive grid from x_min to x_max in steps of ``step`` dB, values rounded to the step's decimals
    (no 0.050000000000000044); refused (ConfigError) above ``max_points`` points or outside ±X_LIMIT_DB."""
    for name, v in (("x_min", x_min), ("x_max", x_max)):
        in_range(name, v, -X_LIMIT_DB, X_LIMIT_DB, unit="dB")
    if not x_min <= x_max:
        raise ConfigError("x_max", x_max, f"is below x_min = {x_min:g} dB")
    positive("step", step, unit="dB")
    count = (x_max - x_min) / step
    if count + 1 > max_points:
        raise ConfigError("step", step, f"gives {count + 1:.3g} points per curve; at most {max_points} here")
    n = math.floor(count + 1e-9) + 1
    decimals = max(0, 9 - math.floor(math.log10(step)))
    return np.round(x_min + step * np.arange(n), decimals)


def parse_figure(text: str) -> FigurePreset:
    """A figure name: '2.4', 'Fig. 2.4', 'fig2.4', 'Figure 2.16' (case and spaces ignored)."""
    m = re.fullmatch(r"\s*(?:fig(?:ure)?\.?\s*)?2\.0*(\d+)\s*", text, flags=re.IGNORECASE)
    preset = FIGURES.get(f"2.{int(m.group(1))}") if m else None
    if preset is None:
        raise ConfigError("figure", text, f"is not a figure of the report; one of {', '.join(FIGURES)}")
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
    """Recompute Table 1.1: the ERP at several P_DL beside the printed row, and both antenna chains (a
    dish model that cannot build a row's dish is a ConfigError on ``antenna``)."""
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
        try:
            inv = jammer_antenna(row["erp_dbw"], rf_dbw=row["rf_dbw"], antenna=antenna)
            fwd = jammer_antenna(row["erp_dbw"], diameter_m=row["diameter_ft"] * FOOT_M, antenna=antenna)
        except ConfigError as exc:
            raise ConfigError("antenna", antenna, f"fails on the K = {K} row: {exc}") from None
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
    """The text's (§2.7) "33 dBW ERP … 30 watts of rf power and an antenna with a 20° beamwidth", recomputed."""
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


# --- the tables of the jam-bound commands -----------------------------------------------------------

LN10 = math.log(10.0)
PF_FORM = {"corrected": "d17", "report": "report"}  # --convention → JammingSystem.pf_form
BOUND_LABEL = {"nfl": r"$\bar N_{FL}/N_T$", "nadl": r"$\bar N_{ADL}/N_T$"}
DEFAULT_PDL = (0.88, 0.999)  # the design P_DL of Table 2.1 and of most figures (K > 1)
SOURCE = "ATC-10 (1972)"

# one panel of jamming_figure: (y label, [(curve label, x_db, log10 N̄/N_T)], [(level, its label)])
Panel = tuple[str, list[tuple[str, np.ndarray, np.ndarray]], list[tuple[float, str]]]


@dataclass(frozen=True)
class JamResult:
    """What a ``jam-bound`` command writes: the table, a one-line summary for stderr and, for the
    curves, the figure's panels and title."""

    table: Table
    summary: str
    panels: list[Panel] = field(default_factory=list)
    title: str = ""


def system_meta(system: JammingSystem) -> dict[str, Any]:
    """The system constants and the p_f convention, as provenance."""
    report = system.pf_form == "report"
    return {
        "convention": "report" if report else "corrected",
        "pf_formula": "p_f = Phi(Phi^-1(p_d) - sqrt(P0 B tau / J)) (eq D.17)"
        + (
            "; N_FL with K > 1 uses the misprinted 1/2 sqrt(P0 B tau / J) of eqs 2.8.1/2.8.3"
            if report
            else ""
        ),
        "B_hz": system.bandwidth_hz,
        "alpha_s": system.alpha_s,
        "beta_s": system.beta_s,
        "vmax_mph": system.vmax_mph,
        "c_mph": system.c_mph,
        "energy_j": system.energy_j,
        "airborne_frac": system.airborne_frac,
        "n_alpha": system.n_alpha,
        "n_beta": system.n_beta,
        "n_v": system.n_v,
        "eb_dbw": system.eb_dbw,
        "units": "bounds are fractions of the population N_T; x_db = 10 log10(J/(P0 B tau)); "
        "erp_dbw = x_db + 10 log10(E B)",
    }


def design_pairs(
    K: int, pdl: Sequence[float] | None, pd: Sequence[float] | None, t: Sequence[float]
) -> list[tuple[float, JammingDesign]]:
    """(P_DL, design) pairs: p_d solved for every (P_DL, t) of ``pdl`` × ``t``, or P_DL computed for every
    (p_d, t) of ``pd`` × ``t``; ``pdl`` and ``pd`` exclude each other. A (p_d, t) with t ≥ q = p_d^S
    (P_DL = 0: the design is infeasible) is a ConfigError on ``t``."""
    if pd is not None and pdl is not None:
        raise ConfigError("pd", list(pd), "is given with P_DL: give the design P_DL or p_d, not both")
    if pd is None:
        assert pdl is not None
        return designs_for(K, pdl, t)
    out = []
    for p in pd:
        for tt in t:
            design = JammingDesign(K, p, tt)
            if design.pdl <= 0.0:
                raise ConfigError(
                    "t",
                    tt,
                    f"is not below q = p_d^{design.satellites} = {design.q:.6g} (p_d = {p:g}): P_DL = 0, "
                    "the design is infeasible",
                )
            out.append((design.pdl, design))
    return out


def _value(log_value: float) -> float | None:
    """N̄/N_T as a float, or None where it underflows a double (the log10 column is exact)."""
    return math.exp(log_value) if log_value > -690.0 else None


@dataclass(frozen=True)
class CurvesConfig:
    """What ``jam-bound curves`` evaluates: a figure preset and/or the bound, K, the designs and the grid.

    None means the default: the preset's value, else K = 10; P_DL 0.88, 0.999 (the P_DL set of Figs
    2.1/2.2 for K = 1); t = 0, 0.1, 0.2, 0.3, 0.5 (0 for K = 1); both bounds; the x range of
    :func:`default_x_range`. ``pdl`` (p_d solved) and ``pd`` (P_DL computed) exclude each other; the
    design values are checked by :class:`JammingDesign` and :func:`p_d_for`. K and ``quantity`` must
    agree with the figure's. x lies within ±X_LIMIT_DB; the table holds at most MAX_ROWS rows.

    Attributes:
        figure: A figure of the report ('2.4', 'Fig. 2.4').
        quantity: nfl, nadl or both.
        K: Tracking length in pulses.
        pdl: Design P_DL values in (0, 1).
        pd: Pulse detection probabilities in (0, 1).
        t: Rule parameters in [0, 1).
        x_min, x_max: The range of x = 10·log10(J/(P₀Bτ)) [dB].
        step: The grid step [dB], > 0.
        system: The system constants.
    """

    figure: str | None = None
    quantity: str | None = None
    K: int | None = None
    pdl: tuple[float, ...] | None = None
    pd: tuple[float, ...] | None = None
    t: tuple[float, ...] | None = None
    x_min: float | None = None
    x_max: float | None = None
    step: float = 0.05
    system: JammingSystem = DEFAULT_SYSTEM

    def __post_init__(self) -> None:
        preset = self.preset
        if preset is not None and self.K is not None and self.K != preset.K:
            raise ConfigError(
                "K", self.K, f"is not the K = {preset.K} of Fig. {preset.figure}; drop K or the figure"
            )
        if self.quantity is not None:
            one_of("quantity", self.quantity, ("nfl", "nadl", "both"))
            if preset is not None and self.quantity != preset.quantity:
                raise ConfigError(
                    "quantity",
                    self.quantity,
                    f"is not what Fig. {preset.figure} shows ({preset.quantity}); drop the quantity or the figure",
                )
        positive("step", self.step, unit="dB")
        _ = self.x  # checks the designs and the grid

    @cached_property
    def preset(self) -> FigurePreset | None:
        """The figure preset, if any."""
        return None if self.figure is None else parse_figure(self.figure)

    @property
    def resolved_K(self) -> int:
        """K, or the figure's, or 10."""
        if self.K is not None:
            return self.K
        return self.preset.K if self.preset else 10

    @property
    def resolved_pdl(self) -> tuple[float, ...] | None:
        """The design P_DL values (None when ``pd`` is given)."""
        if self.pdl is not None or self.pd is not None:
            return self.pdl
        if self.preset:
            return self.preset.pdl
        return DEFAULT_PDL if self.resolved_K > 1 else PDL_SET_K1

    @property
    def resolved_t(self) -> tuple[float, ...]:
        """The rule parameters."""
        if self.t is not None:
            return self.t
        if self.preset:
            return self.preset.t
        return (0.0,) if self.resolved_K == 1 else T_SET

    @property
    def quantities(self) -> list[Quantity]:
        """The bounds drawn."""
        if self.quantity is None:
            return [self.preset.quantity] if self.preset else ["nfl", "nadl"]
        return ["nfl", "nadl"] if self.quantity == "both" else [self.quantity]  # type: ignore[list-item]

    @cached_property
    def designs(self) -> list[tuple[float, JammingDesign]]:
        """(P_DL, design) pairs (:func:`design_pairs`)."""
        return design_pairs(self.resolved_K, self.resolved_pdl, self.pd, self.resolved_t)

    @cached_property
    def x(self) -> np.ndarray:
        """The x grid [dB], at most MAX_ROWS points in all curves together."""
        lo, hi = self.preset.x_range if self.preset else default_x_range(self.resolved_K)
        lo, hi = lo if self.x_min is None else self.x_min, hi if self.x_max is None else self.x_max
        per_curve = MAX_ROWS // (len(self.designs) * len(self.quantities))
        return x_grid(lo, hi, self.step, max_points=per_curve)


def curves_table(config: CurvesConfig) -> JamResult:
    """N̄_FL/N_T and N̄_ADL/N_T against x = 10 log10(J/P₀Bτ) (eqs 2.7.3, 2.8.3, 2.8.4; Figs 2.1–2.16).

    One row per (quantity, design, x); log10_value is exact even where the value underflows a double
    (value is then empty). The panels are those of :func:`motionsig_cli.plotting.jamming_figure`.
    """
    system, preset, K, x = config.system, config.preset, config.resolved_K, config.x
    rows, panels = [], []
    for q in config.quantities:
        lines = []
        for c in curves(q, config.designs, x, system):
            log10_pf = c.log_pf / LN10
            log10_v = c.log_value / LN10
            for xi, lp, lv, v in zip(c.x_db, log10_pf, log10_v, c.log_value, strict=True):
                rows.append(
                    (
                        preset.figure if preset else "",
                        q,
                        K,
                        c.pdl,
                        c.design.t,
                        c.design.p_d,
                        float(xi),
                        float(xi) + system.eb_dbw,
                        float(lp),
                        float(lv),
                        _value(float(v)),
                    )
                )
            lines.append((f"P_DL={c.pdl:g}, t={c.design.t:g} (p_d={c.design.p_d:.4f})", c.x_db, log10_v))
        levels = (
            [(1 - system.airborne_frac, "supremum $N_T - N$")]
            if q == "nfl"
            else [(LEVEL_NADL, "$0.01\\,N_T$")]
        )
        panels.append((BOUND_LABEL[q], lines, levels))
    meta = make_meta(
        "jam-bound curves",
        figure=preset.figure if preset else None,
        quantities=config.quantities,
        K=K,
        pdl=config.resolved_pdl,
        pd=config.pd,
        t=config.resolved_t,
        x_min=float(x[0]),
        x_max=float(x[-1]),
        step=config.step,
        **system_meta(system),
        assumptions="figure presets: P_DL set of Figs 2.1/2.2, the t set of the (p_d, t) legends and the x "
        "ranges are assumptions (the report's figures carry no readable data)",
    )
    cols = (
        "figure",
        "quantity",
        "K",
        "P_DL",
        "t",
        "p_d",
        "x_db",
        "erp_dbw",
        "log10_pf",
        "log10_value",
        "value",
    )
    n = len(config.designs)
    return JamResult(
        Table(columns=cols, rows=rows, meta=meta),
        f"jam-bound curves: {n} design(s) × {len(config.quantities)} bound(s) × {len(x)} points",
        panels,
        f"{f'Fig. {preset.figure}' if preset else ''} K = {K}".strip(),
    )


@dataclass(frozen=True)
class ThresholdConfig:
    """What ``jam-bound threshold`` solves: the jammer power at which a bound reaches a level.

    Attributes:
        quantity: nfl or nadl.
        level: The target N̄/N_T in (0, 1] (:func:`check_level`: an N̄_FL level must be below N_T − N).
        K: Tracking length in pulses.
        pdl: Design P_DL values (default 0.88, 0.999 unless ``pd`` is given).
        pd: Pulse detection probabilities instead of ``pdl``.
        t: Rule parameters in [0, 1).
        system: The system constants.
    """

    quantity: str = "nadl"
    level: float = LEVEL_NADL
    K: int = 10
    pdl: tuple[float, ...] | None = None
    pd: tuple[float, ...] | None = None
    t: tuple[float, ...] = (0.0,)
    system: JammingSystem = DEFAULT_SYSTEM

    def __post_init__(self) -> None:
        one_of("quantity", self.quantity, ("nfl", "nadl"))
        check_level(self.quantity, self.level, self.system)  # type: ignore[arg-type]
        _ = self.designs

    @property
    def resolved_pdl(self) -> tuple[float, ...] | None:
        """The design P_DL values (None when ``pd`` is given)."""
        return DEFAULT_PDL if self.pdl is None and self.pd is None else self.pdl

    @cached_property
    def designs(self) -> list[tuple[float, JammingDesign]]:
        """(P_DL, design) pairs (:func:`design_pairs`)."""
        return design_pairs(self.K, self.resolved_pdl, self.pd, self.t)


def threshold_table(config: ThresholdConfig) -> JamResult:
    """One row per design: the threshold x*, ERP, p_f*, d*, the supremum and the conditioning
    (:func:`required_jamming`)."""
    q, level = config.quantity, config.level
    rows = []
    for target, design in config.designs:
        th = required_jamming(q, level, design, config.system)  # type: ignore[arg-type]
        ok = th.attainable
        rows.append(
            (
                q,
                level,
                config.K,
                target,
                design.t,
                design.p_d,
                ok,
                th.x_db if ok else None,
                th.erp_dbw if ok else None,
                th.log_pf / LN10 if ok else None,
                th.d if ok else None,
                th.log_sup / LN10,
                math.exp(th.log_sup),
                th.pf_over_pd if ok else None,
                th.dlog_per_db if ok else None,
                th.ill_conditioned,
            )
        )
    cols = (
        "quantity",
        "level",
        "K",
        "P_DL",
        "t",
        "p_d",
        "attainable",
        "x_db",
        "erp_dbw",
        "log10_pf",
        "d",
        "log10_sup",
        "sup",
        "pf_over_pd",
        "dlog_per_db",
        "ill_conditioned",
    )
    meta = make_meta(
        "jam-bound threshold", quantity=q, level=level, K=config.K, pdl=config.resolved_pdl, pd=config.pd,
        t=config.t, **system_meta(config.system),
    )  # fmt: skip
    bad = sum(1 for r in rows if not r[6])
    return JamResult(
        Table(columns=cols, rows=rows, meta=meta),
        f"jam-bound threshold: {len(rows)} design(s), {bad} unattainable",
    )


@dataclass(frozen=True)
class TableConfig:
    """Which table of the report ``jam-bound table`` recomputes.

    Attributes:
        which: '2.1' (ERP against K and P_DL) or '1.1' (ERP and the jammer's antenna).
        level: The N̄_ADL target as a fraction of N_T (the report's 0.01), in (0, 1].
        antenna: The dish model of Table 1.1 (checked for Table 2.1 too).
        system: The system constants.
    """

    which: str = "2.1"
    level: float = LEVEL_NADL
    antenna: DishAntenna = DEFAULT_DISH
    system: JammingSystem = DEFAULT_SYSTEM

    def __post_init__(self) -> None:
        one_of("which", self.which, ("2.1", "1.1"))
        check_level("nadl", self.level, self.system)


def report_table(config: TableConfig) -> JamResult:
    """Table 2.1 or 1.1 recomputed, with the printed values, the deviation in dB and the report's internal
    inconsistencies flagged (t = 0 curves, N̄_ADL = level·N_T)."""
    if config.which == "2.1":
        return _table_2_1_result(config)
    return _table_1_1_result(config)


def _table_2_1_result(config: TableConfig) -> JamResult:
    rows21 = table_2_1(config.system, config.level)
    rows = []
    for r in rows21:
        th = r.threshold
        rows.append(
            (
                r.K,
                r.pdl,
                r.design.t,
                r.design.p_d,
                math.exp(th.log_pf) if th.attainable else None,
                th.x_db if th.attainable else None,
                th.erp_dbw if th.attainable else None,
                ("> " if r.relation == ">" else "") + f"{r.printed_dbw:g}",
                r.deviation_db,
                r.tolerance_db,
                r.status,
                math.exp(th.log_sup),
                th.pf_over_pd if th.attainable else None,
            )
        )
    cols = (
        "K",
        "P_DL",
        "t",
        "p_d",
        "p_f",
        "x_db",
        "erp_dbw",
        "printed_erp_dbw",
        "deviation_db",
        "tolerance_db",
        "status",
        "sup_nadl",
        "pf_over_pd",
    )
    meta = make_meta(
        "jam-bound table",
        which="2.1",
        source=f"{SOURCE} Table 2.1",
        level=config.level,
        **system_meta(config.system),
    )
    agree = sum(r.status in ("agrees", "unattainable-as-printed") for r in rows21)
    return JamResult(
        Table(columns=cols, rows=rows, meta=meta),
        f"Table 2.1: {agree}/{len(rows21)} rows agree with the printed values within tolerance",
    )


def _table_1_1_result(config: TableConfig) -> JamResult:
    antenna = config.antenna
    rows11 = table_1_1(config.system, antenna, config.level)
    printed21 = {(r.K, r.pdl): r for r in table_2_1(config.system, config.level)}
    rows = []
    for r in rows11:
        flags = r.flags()
        in21 = {p: v for (k, p), v in printed21.items() if k == r.K and v.relation == "="}
        if in21 and not any(v.printed_dbw == r.printed["erp_dbw"] for v in in21.values()):
            flags.append(
                "Table 2.1 prints "
                + ", ".join(f"{v.printed_dbw:g} dBW for P_DL {p:g}" for p, v in in21.items())
                + f", not {r.printed['erp_dbw']:g}"
            )
        cap = r.erp_by_pdl.get(r.caption_pdl)
        rows.append(
            (
                r.K,
                *[r.erp_by_pdl[p] for p in TABLE_1_1_PDL],
                r.printed["erp_dbw"],
                None if cap is None else cap - r.printed["erp_dbw"],
                ";".join(f"{p:g}" for p in r.matches),
                r.printed["rf_dbw"],
                r.inverse["gain_dbi"],
                r.inverse["diameter_ft"],
                r.printed["diameter_ft"],
                r.inverse["beamwidth_deg"],
                r.printed["beamwidth_deg"],
                r.forward["rf_dbw"],
                r.forward["beamwidth_deg"],
                "; ".join(flags),
            )
        )
    cols = (
        "K",
        *[f"erp_dbw_pdl_{p:g}" for p in TABLE_1_1_PDL],
        "printed_erp_dbw",
        "deviation_caption_db",
        "matching_pdl",
        "printed_rf_dbw",
        "gain_dbi",
        "diameter_ft",
        "printed_diameter_ft",
        "beamwidth_deg",
        "printed_beamwidth_deg",
        "rf_dbw_from_diameter",
        "beamwidth_deg_from_diameter",
        "flags",
    )
    anchor = text_anchor_k1(antenna)
    meta = make_meta(
        "jam-bound table",
        which="1.1",
        source=f"{SOURCE} Table 1.1",
        caption_pdl=rows11[0].caption_pdl,
        antenna={
            "freq_hz": antenna.freq_hz,
            "eta": antenna.efficiency,
            "bw_const": antenna.beamwidth_const_deg,
            "model": "G = eta (pi D / lambda)^2, theta = k lambda / D",
        },
        text_anchor_k1=anchor,
        chains="diameter_ft, beamwidth_deg: inverse chain from the printed ERP and rf power; "
        "*_from_diameter: forward chain from the printed ERP and diameter",
        level=config.level,
        **system_meta(config.system),
    )
    flagged = sum(1 for r in rows if r[-1])
    return JamResult(
        Table(columns=cols, rows=rows, meta=meta),
        f"Table 1.1: {flagged} of {len(rows)} rows carry a flagged inconsistency; "
        f"text anchor (33 dBW, 30 W) gives {anchor['beamwidth_deg']:.1f} deg vs printed 20",
    )


def design_table(
    K: int, pdl: float | None = None, pd: float | None = None, t: float | None = None
) -> JamResult:
    """The first-stage design (App. A) from two of p_d, P_DL and t (t = 0 when only one is given): p_d
    from (K, P_DL, t) (eq 2.4.2 inverted), P_DL from (K, p_d, t) (eqs 2.4.1–2.4.2), or t from (K, p_d,
    P_DL); with the Chernoff parameter ν* and the exponent E(t, q) = D(t‖q), q = p_d^4 (A.17–A.18)."""
    if pd is not None and pdl is not None:
        if t is not None:
            raise ConfigError(
                "t", t, "is given with p_d and P_DL: give two of them (t is solved from p_d and P_DL)"
            )
        d, solved = JammingDesign(K, pd, t_for(K, pd, pdl)), "t"
    elif pd is not None:
        d, solved = JammingDesign(K, pd, t or 0.0), "P_DL"
    elif pdl is not None:
        d, solved = JammingDesign.from_pdl(K, pdl, t or 0.0), "p_d"
    else:
        raise ConfigError(
            "pdl",
            None,
            "is missing, and so is p_d: give P_DL (solve p_d), p_d (compute P_DL) or both (solve t)",
        )
    meta = make_meta(
        "jam-bound design",
        K=K,
        pdl=pdl,
        pd=pd,
        t=t,
        rule="declare present iff more than K t of the K lists are non-empty (A.11)",
    )
    cols = ("K", "t", "p_d", "q", "P_DL", "nu", "exponent", "solved")
    row = (K, d.t, d.p_d, d.q, d.pdl, d.nu, d.exponent, solved)
    return JamResult(
        Table(columns=cols, rows=[row], meta=meta), f"jam-bound design: solved {solved}; P_DL = {d.pdl:.10g}"
    )


def antenna_table(
    erp_dbw: float,
    *,
    rf_dbw: float | None = None,
    rf_w: float | None = None,
    diameter_ft: float | None = None,
    dish: DishAntenna = DEFAULT_DISH,
) -> JamResult:
    """The jammer's dish from the ERP and exactly one of the rf power (dBW or W) and the diameter (ft):
    the rest of a Table 1.1 row (:func:`jammer_antenna`)."""
    given = {"rf_dbw": rf_dbw, "rf_w": rf_w, "diameter_ft": diameter_ft}
    named = [k for k, v in given.items() if v is not None]
    if len(named) != 1:
        what = "give exactly one of the rf power (rf_dbw or rf_w) and the dish diameter (diameter_ft)"
        if not named:
            raise ConfigError("rf_dbw", None, f"is missing, and so are rf_w and diameter_ft: {what}")
        raise ConfigError(named[1], given[named[1]], f"is given with {named[0]}: {what}")
    if rf_w is not None:
        positive("rf_w", rf_w, unit="W")
    if diameter_ft is not None:
        positive("diameter_ft", diameter_ft, unit="ft")
    rf = rf_dbw if rf_dbw is not None else 10 * math.log10(rf_w) if rf_w is not None else None
    try:
        tx = jammer_antenna(
            erp_dbw, rf_dbw=rf, diameter_m=None if diameter_ft is None else diameter_ft * FOOT_M, antenna=dish
        )
    except ConfigError as exc:
        if exc.field in ("rf_dbw", "diameter_m") and exc.field != named[0]:
            raise ConfigError(named[0], given[named[0]], exc.reason) from None
        raise
    cols = ("erp_dbw", "rf_dbw", "rf_w", "gain_dbi", "diameter_ft", "diameter_m", "beamwidth_deg")
    row = (tx.erp_dbw, tx.rf_dbw, tx.rf_w, tx.gain_dbi, tx.diameter_ft, tx.diameter_m, tx.beamwidth_deg)
    meta = make_meta(
        "jam-bound antenna",
        freq_hz=dish.freq_hz,
        eta=dish.efficiency,
        bw_const=dish.beamwidth_const_deg,
        given="--" + named[0].replace("_", "-"),
        model="ERP = P_rf + G, G = eta (pi D / lambda)^2, theta = k lambda / D",
    )
    return JamResult(
        Table(columns=cols, rows=[row], meta=meta),
        f"jam-bound antenna: G = {tx.gain_dbi:.2f} dBi, D = {tx.diameter_ft:.2f} ft, θ = {tx.beamwidth_deg:.1f}°",
    )
