"""The LMP detector's result on one record, as ``motionsig detect`` reports it: the argmax of eq (52) per
horizon (or every candidate's statistic), the Fig 3-style grid of the statistic, and a summary line (the
1-D and the 2-D radar records share it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from motionsig_cli.tables import Table, make_meta

if TYPE_CHECKING:
    from motionsig_cli.detection.lmp import LMPResult
    from motionsig_cli.filters.unscented import SigmaPointParams

CANDIDATE_COLUMNS = ("horizon_s", "mode", "tau", "tau_chips", "f_c", "J0", "J_cos", "J_sin", "Lambda")


def sigma_meta(sigma: SigmaPointParams, repairs: tuple[int, int]) -> dict[str, Any]:
    """Metadata of a sigma-point run: the unscented-transform parameters and the covariance repairs."""
    return {
        "ut_alpha": sigma.alpha,
        "ut_beta": sigma.beta,
        "ut_kappa": sigma.kappa,
        "covariance_repairs_state": repairs[0],
        "covariance_repairs_innovation": repairs[1],
    }


@dataclass(frozen=True)
class RecordResult:
    """The detector's result on one record.

    Attributes:
        table: The argmax per horizon (with the truth and the decision when known), or with
            ``candidates`` every candidate's J0, J_cos, J_sin and Λ per horizon.
        res: The detector's output.
        truth: (0-based mode, τ) of the record, or None.
        n_modes: Modes of the code table.
        m_rho: Samples per chip.
        summary: One line for people (the last horizon).
    """

    table: Table
    res: LMPResult
    truth: tuple[int, int] | None
    n_modes: int
    m_rho: int
    summary: str

    def statistic_grid(self) -> tuple[np.ndarray, tuple[int, int] | None, np.ndarray]:
        """Λ at the last horizon on the (mode, τ) grid of the first carrier (Fig 3), the truth's cell
        (mode, τ index) when it lies on the grid, and the grid's code phases in chips."""
        cands = self.res.candidates
        taus = np.unique(cands.tau)
        n_fc = len(np.unique(cands.f_c))
        lam = self.res.Lambda[:, 0, -1].reshape(self.n_modes, taus.size, n_fc)[:, :, 0]
        truth = self.truth
        cell = (
            (truth[0], int(np.searchsorted(taus, truth[1])))
            if truth is not None and truth[1] in taus
            else None
        )
        return lam, cell, taus / self.m_rho


def record_result(
    res: LMPResult,
    hs: list[float],
    hz: list[int],
    truth: tuple[int, int] | None,
    params: dict[str, Any],
    chips_shape: tuple[int, int],
    m_rho: int,
    *,
    candidates: bool,
    threshold: float | Sequence[float] | None,
    notes: Sequence[str] = (),
) -> RecordResult:
    """Tabulate the detector's result at horizons ``hs`` seconds (``hz`` samples); ``params`` (the detector
    settings) go into the metadata with the number of candidates and filters.

    A horizon's estimate is correct when the mode matches and the code phase matches modulo the code
    period n_ρ m_ρ; with a ``threshold`` the decision is a column: λ* ≥ threshold for one threshold (a
    fixed ``--threshold``), λ* > threshold for one per horizon (a threshold calibrated on null records,
    the order statistic that at most ⌊P_FA n⌋ null maxima exceed; a ``threshold`` column precedes it).
    ``notes`` are appended to the summary line, which without a threshold says that the argmax is no
    decision.
    """
    per_horizon = threshold is not None and not isinstance(threshold, int | float)
    thresholds: list[float] | None = None
    if threshold is not None:
        thresholds = [float(v) for v in threshold] if per_horizon else [float(threshold)] * len(hz)  # type: ignore[union-attr]
    cands = res.candidates
    best, lam_max = res.best()
    margin = res.runner_up_margin()
    n_modes, n_rho = chips_shape
    period = n_rho * m_rho  # the code repeats every n_ρ m_ρ samples
    params = {**params, "n_candidates": len(cands), "n_filters": 1 + 2 * len(cands)}
    if candidates:
        rows: list[tuple[Any, ...]] = [
            (
                hs[h],
                int(cands.mode[c]) + 1,
                int(cands.tau[c]),
                cands.tau[c] / m_rho,
                float(cands.f_c[c]),
                float(res.J0[0, h]),
                float(res.J_cos[c, 0, h]),
                float(res.J_sin[c, 0, h]),
                float(res.Lambda[c, 0, h]),
            )
            for h in range(len(hz))
            for c in range(len(cands))
        ]
        table = Table(CANDIDATE_COLUMNS, rows, make_meta("detect", **params))
    else:
        rows = []
        for h in range(len(hz)):
            c = int(best[0, h])
            row: list[Any] = [
                hs[h],
                hz[h],
                int(cands.mode[c]) + 1,
                int(cands.tau[c]),
                cands.tau[c] / m_rho,
                float(cands.f_c[c]),
                float(lam_max[0, h]),
                float(margin[0, h]),
                float(res.J0[0, h]),
            ]
            if truth is not None:
                row += [
                    truth[0] + 1,
                    truth[1],
                    int(cands.mode[c]) == truth[0] and int(cands.tau[c]) % period == truth[1] % period,
                ]
            if thresholds is not None:
                row += [thresholds[h]] if per_horizon else []
                row.append(_present(float(lam_max[0, h]), thresholds[h], per_horizon))
            rows.append(tuple(row))
        cols = ["horizon_s", "horizon_samples", "mode_hat", "tau_hat", "tau_hat_chips", "fc_hat"]
        cols += ["statistic", "margin", "J0"]
        if truth is not None:
            cols += ["true_mode", "true_tau", "correct"]
        if threshold is not None:
            cols += ["threshold", "signature_present"] if per_horizon else ["signature_present"]
        table = Table(tuple(cols), rows, make_meta("detect", **params))
    c = int(best[0, -1])
    present_last = thresholds is not None and _present(float(lam_max[0, -1]), thresholds[-1], per_horizon)
    carrier = f", carrier {cands.f_c[c]:g} Hz" if np.unique(cands.f_c).size > 1 else ""  # a carrier search
    summary = (
        f"horizon {hs[-1]:g} s: mode {cands.mode[c] + 1}, tau {cands.tau[c]} samples "
        f"({cands.tau[c] / m_rho:g} chips){carrier}, statistic {lam_max[0, -1]:.4g}, margin {margin[0, -1]:.3g}"
        + ("" if truth is None else f"; truth mode {truth[0] + 1}, tau {truth[1]}")
        + (f"; {sum(res.repairs)} covariance repairs" if sum(res.repairs) else "")
        + "".join(f"; {n}" for n in notes)
        + (
            "; the argmax is reported whether or not a signature is present: --pfa P (or --threshold X) "
            "tests for one"
            if thresholds is None
            else f"; signature {'present' if present_last else 'absent'} (threshold {thresholds[-1]:.4g})"
        )
    )
    return RecordResult(table, res, truth, n_modes, m_rho, summary)


def _present(lam_max: float, threshold: float, calibrated: bool) -> bool:
    """The decision "signature present": λ* > a calibrated threshold, λ* ≥ a fixed one."""
    return lam_max > threshold if calibrated else lam_max >= threshold
