"""Reading ``simulate`` records and writing ``detect``'s per-record result (shared by the 1-D and the
2-D radar paths of ``motionsig detect``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import typer

from motionsig_cli.cli.common import OutputFormat, checked, float_list, note, save_figure
from motionsig_cli.cli.io import InputError, Table, emit, make_meta
from motionsig_cli.detection.lmp import LMPResult
from motionsig_cli.filters.unscented import SigmaPointParams


def parse_horizons(text: str | None, duration: float, T: float) -> list[float]:
    """--horizons in seconds (default every 10 s of the record), each within the record."""
    if text is None:
        return [float(h) for h in range(10, math.floor(duration + 1e-9) + 1, 10)] or [duration]
    hs = checked("--horizons", float_list, text, what="horizon")
    if min(hs) <= 0:
        raise typer.BadParameter("horizons must be > 0 seconds", param_hint="--horizons")
    if max(hs) > duration + 1e-9:
        raise typer.BadParameter(
            f"horizon {max(hs):g} s is longer than the record ({duration:g} s)", param_hint="--horizons"
        )
    if round(min(hs) / T) < 1:
        raise typer.BadParameter(
            f"horizon {min(hs):g} s is shorter than one sample (T = {T:g} s)", param_hint="--horizons"
        )
    return hs


def finite_column(t: Table, name: str) -> np.ndarray:
    """A numeric column whose every value is finite (else an error naming file:line)."""
    arr = t.numeric(name)
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise InputError(f"{t.source}:{t.lines[bad[0]]}: column {name!r} is not finite")
    return arr


def uniform_times(t: Table) -> np.ndarray:
    """Column ``t``: at least 2 finite samples, increasing, spaced by the metadata ``T``."""
    times = t.numeric("t")
    if times.size < 2:
        raise InputError(f"{t.source}: need at least 2 samples")
    times = finite_column(t, "t")
    try:
        T = float(t.meta["T"])
        if not (math.isfinite(T) and T > 0):
            raise ValueError
    except (TypeError, ValueError):
        raise InputError(f"{t.source}: metadata 'T' must be a positive number, got {t.meta['T']!r}") from None
    dt = np.diff(times)
    if np.any(dt <= 0):
        i = int(np.flatnonzero(dt <= 0)[0]) + 1
        raise InputError(f"{t.source}:{t.lines[i]}: time is not increasing")
    if np.max(np.abs(dt - T)) > 1e-6 * max(T, 1.0):
        i = int(np.argmax(np.abs(dt - T))) + 1
        raise InputError(
            f"{t.source}:{t.lines[i]}: time step {dt[i - 1]:g} differs from the metadata T = {T:g} (non-uniform time)"
        )
    return times


def truth_of(meta: dict[str, Any]) -> tuple[int, int] | None:
    """(0-based mode, τ) recorded by ``simulate``, or None (no signature, or not recorded)."""
    if "mode" in meta and "tau" in meta and meta.get("signature", True):
        return int(meta["mode"]) - 1, int(meta["tau"])
    return None


def sigma_meta(sigma: SigmaPointParams, repairs: tuple[int, int]) -> dict[str, Any]:
    """Metadata of a sigma-point run: the UT parameters and the covariance repairs."""
    return {
        "ut_alpha": sigma.alpha,
        "ut_beta": sigma.beta,
        "ut_kappa": sigma.kappa,
        "covariance_repairs_state": repairs[0],
        "covariance_repairs_innovation": repairs[1],
    }


def emit_record_result(
    res: LMPResult,
    hs: list[float],
    hz: list[int],
    truth: tuple[int, int] | None,
    params: dict[str, Any],
    chips_shape: tuple[int, int],
    m_rho: int,
    title: str,
    *,
    candidates: bool,
    threshold: float | None,
    plot: Path | None,
    fmt: OutputFormat,
    out: Path | None,
    quiet: bool,
) -> None:
    """The argmax per horizon (or the whole candidate table), the Fig 3-style plot, a summary line."""
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
        table = Table(
            ("horizon_s", "mode", "tau", "tau_chips", "f_c", "J0", "J_cos", "J_sin", "Lambda"),
            rows,
            make_meta("detect", **params),
        )
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
            if threshold is not None:
                row.append(bool(lam_max[0, h] >= threshold))
            rows.append(tuple(row))
        cols = ["horizon_s", "horizon_samples", "mode_hat", "tau_hat", "tau_hat_chips", "fc_hat"]
        cols += ["statistic", "margin", "J0"]
        if truth is not None:
            cols += ["true_mode", "true_tau", "correct"]
        if threshold is not None:
            cols.append("signature_present")
        table = Table(tuple(cols), rows, make_meta("detect", **params))
    if plot is not None:
        from motionsig_cli.plotting import statistic_figure

        taus = np.unique(cands.tau)
        n_fc = len(np.unique(cands.f_c))
        lam = res.Lambda[:, 0, -1].reshape(n_modes, taus.size, n_fc)[:, :, 0]
        tr = (
            (truth[0], int(np.searchsorted(taus, truth[1])))
            if truth is not None and truth[1] in taus
            else None
        )
        save_figure(statistic_figure([(title, lam, tr)], n_modes, taus / m_rho), plot)
    emit(table, fmt.value, out)
    c = int(best[0, -1])
    note(
        f"horizon {hs[-1]:g} s: mode {cands.mode[c] + 1}, tau {cands.tau[c]} samples "
        f"({cands.tau[c] / m_rho:g} chips), statistic {lam_max[0, -1]:.4g}, margin {margin[0, -1]:.3g}"
        + ("" if truth is None else f"; truth mode {truth[0] + 1}, tau {truth[1]}")
        + (f"; {sum(res.repairs)} covariance repairs" if sum(res.repairs) else ""),
        quiet,
    )
