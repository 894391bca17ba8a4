"""Figure builders (the only module that imports matplotlib). Each returns a ``Figure``; no pyplot.

"The mode-signature paper" is 47th IEEE CDC, Cancún, 2008; "the SLRT
slides" are Govaers, *Evaluation of Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE);
"the maneuver paper" is Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from motionsig_cli.signals.signature import Signature


def _wrap(text: str, width: int) -> str:
    """``text`` broken after its ", " / "; " separators into lines of at most ``width`` characters (a title
    that would otherwise run past its panel or the figure; a part longer than ``width`` keeps its line)."""
    if len(text) <= width:
        return text
    parts: list[str] = []
    start = 0
    for i, ch in enumerate(text):
        if ch in ",;" and text[i + 1 : i + 2] == " ":
            parts.append(text[start : i + 1])
            start = i + 2
    parts.append(text[start:])
    lines = [parts[0]]
    for part in parts[1:]:
        if len(lines[-1]) + 1 + len(part) <= width:
            lines[-1] += " " + part
        else:
            lines.append(part)
    return "\n".join(lines)


def signature_figure(sig: Signature, *, title: str = "", theta: float = 0.0, f_c: float = 1.0) -> Figure:
    """Chips p_k[τ], carrier cos(2π f_c t_k + θ) and signature z_k (eqs 1–3 of the mode-signature paper), stacked."""
    fig = Figure(figsize=(8, 5.5), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    axes[0].step(sig.t, sig.p, where="post", color="C0")
    axes[0].set_ylabel(r"chip $p_k[\tau]$")
    axes[0].set_ylim(-1.4, 1.4)
    carrier = np.cos(2 * np.pi * f_c * sig.t + theta)
    axes[1].plot(sig.t, carrier, color="C1")
    axes[1].set_ylabel(r"$\cos(2\pi f_c t_k + \theta)$")
    axes[2].plot(sig.t, sig.z, color="C2", label=r"$z_k$")
    axes[2].plot(sig.t, sig.z_cos, color="0.6", lw=0.8, ls="--", label=r"$z_{\cos,k}$ replica")
    axes[2].set_ylabel(r"signature $z_k$")
    axes[2].set_xlabel("time t [s]")
    top = max(float(np.max(np.abs(sig.z), initial=0.0)), float(np.max(np.abs(sig.z_cos), initial=0.0)), 1e-12)
    axes[2].set_ylim(-1.2 * top, 2.0 * top)  # headroom above the waveform for the legend
    axes[2].set_yticks([-top, 0.0, top], [f"−{top:.3g}", "0", f"{top:.3g}"])
    axes[2].legend(loc="upper right", fontsize="small", ncol=2)
    for ax in axes:
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    return fig


def correlation_figure(lags: np.ndarray, values: np.ndarray, labels: list[str], bound: int | None) -> Figure:
    """Periodic correlation R[ℓ] against lag, one panel per code pair (stacked, shared lag axis), with the
    ±t(n) lines. A peak far above the rest of its curve (R[0] = n of an autocorrelation) is cut at the top
    of its panel and its value written there, so that the side lobes, the point of the figure, stay
    readable; codes longer than 64 chips are drawn as dots without lines."""
    n_pairs = len(labels)
    fig = Figure(figsize=(8, 0.6 + 1.25 * n_pairs), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n_pairs, 1, sharex=True, squeeze=False)).ravel()
    dense = len(lags) > 64
    style = dict(ls="none", marker=".", ms=2.0) if dense else dict(marker=".", ms=4, lw=0.8)
    for i, (ax, v, lab) in enumerate(zip(axes, values, labels, strict=True)):
        mag = np.abs(v)
        peak = int(np.argmax(mag))
        rest = np.delete(mag, peak)
        side = float(rest.max()) if rest.size else float(mag[peak])
        ref = max(side, float(bound) if bound is not None else 0.0, 1.0)
        ax.plot(lags, v, color=f"C{i % 10}", **style)
        ax.set_ylim(-1.45 * ref, 1.45 * ref)  # the top 15 % stays free for the note of a cut peak
        if mag[peak] > 2.0 * ref:  # an autocorrelation peak: cut at the top, its value written there
            ax.text(
                0.995,
                0.97,
                f"R[{lags[peak]:g}] = {v[peak]:g} (off scale)",
                transform=ax.transAxes,
                ha="right",
                va="top",
                fontsize="x-small",
            )
        if bound is not None:
            for y in (-bound, bound - 2):
                ax.axhline(y, color="k", lw=0.6, ls=":")
        ax.set_ylabel(lab, fontsize="small")
        ax.grid(alpha=0.3)
    ax0 = axes[0]
    ax0.set_title(
        "periodic correlation R[ℓ]"
        + ("" if bound is None else f"; dotted: −t(n) and t(n) − 2, t(n) = {bound}"),
        fontsize="medium",
    )
    axes[-1].set_xlabel("lag ℓ [chips]")
    axes[-1].set_xlim(lags[0] - 0.01 * (lags[-1] - lags[0] + 1), lags[-1] + 0.01 * (lags[-1] - lags[0] + 1))
    return fig


def response_figure(
    t: np.ndarray, x: np.ndarray, r: np.ndarray, r_total: np.ndarray, y: np.ndarray
) -> Figure:
    """Fig 2 of the mode-signature paper: the 1-D closed loop following the combined reference r + a_sig z."""
    fig = Figure(figsize=(8, 4), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(t, r, color="0.6", lw=1, ls="--", label="nominal reference $r_k$")
    ax.plot(t, r_total, color="C1", lw=0.8, label="combined reference $r_k + a_{sig} z_k$")
    ax.plot(t, x, color="C0", lw=1.2, label="position $x_k$")
    ax.plot(t, y, ".", color="C3", ms=1.5, alpha=0.4, label="measurement $y_k$")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position [m]")
    # above the axes: the loop's response fills the plane, so no place inside it is free of the curves
    fig.legend(fontsize="small", loc="outside upper center", ncol=4, markerscale=4)
    ax.grid(alpha=0.3)
    return fig


def statistic_figure(
    panels: list[tuple[str, np.ndarray, tuple[int, int] | None]], n_modes: int, tau_chips: np.ndarray
) -> Figure:
    """Fig 3 of the mode-signature paper: the LMP statistic Λ(i, τ) of single runs, one curve per mode, truth marked.

    Args:
        panels: (title, Λ of shape (n_modes, n_tau), true (mode, tau_index) or None) per panel.
    """
    cols = 2 if len(panels) > 1 else 1
    rows = (len(panels) + cols - 1) // cols
    fig = Figure(figsize=(5 * cols, 3.2 * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for ax, (title, lam, truth) in zip(axes, panels, strict=False):
        for i in range(n_modes):
            ax.plot(tau_chips, lam[i], marker=".", lw=0.8, label=f"mode {i + 1}")
        if truth is not None:
            ax.plot(tau_chips[truth[1]], lam[truth], "k*", ms=12, label="truth")
        ax.set_title(_wrap(title, 50), fontsize="medium")
        ax.set_xlabel("candidate code phase τ [chips]")
        ax.set_ylabel("Λ(i, τ)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize="small")
    return fig


def montecarlo_figure(
    horizons: np.ndarray, curves: dict[float, dict[str, tuple[np.ndarray, np.ndarray]]], title: str = ""
) -> Figure:
    """Figs 4–6 of the mode-signature paper: % correct (i, τ) vs horizon, one line per ANR, one panel per f_r.

    Args:
        curves: f_r → {ANR label → (pct, se)}.
    """
    fig = Figure(figsize=(4.2 * len(curves), 3.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(curves), sharey=True, squeeze=False)).ravel()
    for ax, (fr, by_anr) in zip(axes, curves.items(), strict=True):
        for label, (pct, se) in by_anr.items():
            ax.errorbar(horizons, pct, yerr=se, marker="o", ms=3, capsize=2, lw=1, label=label)
        ax.set_title(f"$f_r$ = {fr:g} Hz")
        ax.set_xlabel("estimation horizon [s]")
        ax.set_ylim(-3, 103)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("% correct (i, τ)")
    axes[0].legend(title="ANR (paper's label)", fontsize="small")
    if title:
        fig.suptitle(title)
    return fig


ZOOM_BELOW = 0.15  # a jamming panel gets an inset when its curves rise within this fraction of its width


def _rise_span(lines: list[tuple[str, np.ndarray, np.ndarray]], y_floor: float) -> tuple[float, float] | None:
    """The J/P₀Bτ span [dB] over which the curves rise: from the first abscissa where one of them leaves
    the bottom of the panel (y_floor) to the last where one reaches 95 % of its own largest value."""
    lo, hi = np.inf, -np.inf
    floor = np.log10(y_floor)
    for _, x, log10_y in lines:
        x, ly = np.asarray(x, float), np.asarray(log10_y, float)
        up = np.flatnonzero(ly > floor)
        if up.size == 0:
            continue
        top = np.flatnonzero(ly >= np.nanmax(ly) + np.log10(0.95))
        lo, hi = min(lo, x[up[0]]), max(hi, x[top[0]])
    return (float(lo), float(hi)) if lo < hi else None


def zoom_rise(ax: Axes, lines: list[tuple[str, np.ndarray, np.ndarray]], ylim: tuple[float, float]) -> bool:
    """Add :func:`_rise_inset` to a jamming panel (lines as in :func:`jamming_figure`) whose curves rise
    within ZOOM_BELOW of its width, in its left half. Returns whether it did (the legend then belongs at
    the lower right)."""
    rise = _rise_span(lines, ylim[0])
    x0, x1 = ax.get_xlim()
    if rise is None or rise[1] - rise[0] >= ZOOM_BELOW * (x1 - x0) or rise[1] >= x0 + 0.5 * (x1 - x0):
        return False
    _rise_inset(ax, lines, rise, ylim)
    return True


def _rise_inset(ax: Axes, lines: list[tuple[str, np.ndarray, np.ndarray]], rise: tuple[float, float],
                ylim: tuple[float, float]) -> None:  # fmt: skip
    """A zoom on the span where the curves rise (a few dB of a panel a hundred wide), right of that span (in
    the left half of the panel), below the curves' plateau near the top and above the legend at the lower
    right."""
    pad = 0.15 * (rise[1] - rise[0])
    x0, x1 = ax.get_xlim()
    left = max(0.3, (rise[1] + pad - x0) / (x1 - x0) + 0.08)  # right of the framed span: covers no rise
    ins = ax.inset_axes((left, 0.44, min(0.38, 0.96 - left), 0.42))
    for _, x, log10_y in lines:
        ins.semilogy(x, 10.0 ** np.maximum(log10_y, -300.0), lw=1.3)
    ins.set_xlim(rise[0] - pad, rise[1] + pad)
    ins.set_ylim(*ylim)
    ins.set_title(f"zoom: {rise[0] - pad:.1f} to {rise[1] + pad:.1f} dB", fontsize="x-small")
    ins.tick_params(labelsize="x-small")
    ins.grid(alpha=0.3, which="both")
    frame = ax.indicate_inset_zoom(ins, edgecolor="0.4")  # the zoomed span, framed on the panel
    for line in frame.connectors:  # connectors would cross the curves and the legend
        line.set_visible(False)


def jamming_figure(
    panels: list[tuple[str, list[tuple[str, np.ndarray, np.ndarray]], list[tuple[float, str]]]],
    title: str = "",
    ylim: tuple[float, float] = (1e-6, 1.5),
) -> Figure:
    """ATC-10 Figs 2.1–2.16: N̄/N_T against 10·log10(J/P₀Bτ) on a log ordinate, one panel per quantity.

    Args:
        panels: (y label, [(curve label, x_db, log10 N̄/N_T)], [(reference level, its label)]).
    """
    fig = Figure(figsize=(6.4 * len(panels), 4.4), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(panels), squeeze=False)).ravel()
    for ax, (ylabel, lines, levels) in zip(axes, panels, strict=True):
        for label, x, log10_y in lines:
            ax.semilogy(x, 10.0 ** np.maximum(log10_y, -300.0), lw=1.3, label=label)
        for level, label in levels:
            ax.axhline(level, color="0.4", ls=":", lw=1)
            ax.annotate(
                label,
                (0.01, level),
                xycoords=("axes fraction", "data"),
                fontsize="x-small",
                va="bottom",
                color="0.3",
            )
        ax.set_ylim(*ylim)
        ax.set_xlabel(r"$10\log_{10}\,J/(P_0 B\tau)$ [dB]")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3, which="both")
        if zoom_rise(ax, lines, ylim):
            ax.legend(fontsize="small", loc="lower right")  # the inset sits above the middle, clear of it
        else:
            ax.legend(fontsize="small", loc="best")
    if title:
        fig.suptitle(title)
    return fig


def psi_figure(alpha: np.ndarray, exact: np.ndarray, large: np.ndarray, small: np.ndarray,
               marks: list[tuple[float, float, str]] = ()) -> Figure:  # fmt: skip
    """ATC-10 Fig 4.1: ψ(α) and its two approximations on a log α axis (each drawn where it is
    meaningful: the large-α form for α ≥ 0.15, the small-α form for α ≤ 1), with Table 4.3's points."""
    fig = Figure(figsize=(7, 4.2), layout="constrained")
    ax = fig.add_subplot()
    ax.semilogx(alpha, exact, color="k", lw=1.6, label=r"$\psi(\alpha)$ exact (4.5.34)")
    sel = alpha >= 0.15
    ax.semilogx(alpha[sel], large[sel], "--", color="C0", label=r"$1 - 4/(27\alpha)$ ($\alpha \geq 1$)")
    sel = alpha <= 1.0
    ax.semilogx(
        alpha[sel],
        small[sel],
        "-.",
        color="C3",
        label=r"$1.89[\alpha^{1/3} - (\alpha/2)^{2/3}]$ ($\alpha \leq 0.3$)",
    )
    for i, (a, p, label) in enumerate(marks):
        ax.plot(a, p, "o", mfc="none", color="C2", label="Table 4.3 (printed)" if i == 0 else None)
        # off the rising curve: below right, or above left where below right would be cut off by the bottom
        # edge (ψ < 0.1) or cross the small-α form (0.5 < ψ < 0.85); above left of ψ > 0.85 is the legend
        low = p < 0.1 or 0.5 < p < 0.85
        ax.annotate(
            label,
            (a, p),
            textcoords="offset points",
            xytext=(-4, 5) if low else (4, -10),
            ha="right" if low else "left",
            fontsize="x-small",
        )
    ax.set_ylim(0, 1.02)
    ax.set_xlabel(r"$\alpha = (8/27)\,\sigma_0^2\beta/\sigma^2$")
    ax.set_ylabel(r"$\psi(\alpha)$")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small", loc="upper left")
    return fig


def rms_error_figure(
    n: np.ndarray,
    series: list[tuple[str, np.ndarray, dict[str, object]]],
    *,
    outage: tuple[int, int] | None = None,
    title: str = "",
    bands: list[tuple[np.ndarray, np.ndarray, str]] = (),
    unit: str = "ft",
) -> Figure:
    """ATC-10 Figs 4.2/4.3: RMS position error (in ``unit``, the report's feet by default) against update
    number n on a log ordinate, with the three-satellite outage shaded. ``series`` = (label, values,
    matplotlib style)."""
    fig = Figure(figsize=(8, 4.6), layout="constrained")
    ax = fig.add_subplot()
    if outage is not None and outage[1] > outage[0]:
        ax.axvspan(outage[0], outage[1], color="0.92", label="3 satellites (outage)")
    for lo, hi, color in bands:
        ax.fill_between(n, lo, hi, color=color, alpha=0.25, lw=0)
    for label, y, style in series:
        ax.semilogy(n, y, label=label, **style)
    ax.set_xlabel("update n (one per second)")
    ax.set_ylabel(rf"RMS position error $\sqrt{{E\|\xi_{{p_n}}\|^2}}$ [{unit}]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="x-small", ncol=2, loc="upper left")
    if title:
        ax.set_title(title)
    return fig


def slrt_figure(panels: list[tuple[str, np.ndarray, dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]]],
                thresholds: tuple[float, float] | None = None) -> Figure:  # fmt: skip
    """The figures of the SLRT slides: mean log LR against scan, one panel per case, methods overlaid, with the 5–95 %
    band over runs. ``panels`` = (title, scans, {method: (mean, q05, q95)})."""
    n = len(panels)
    cols = min(n, 2)
    rows = (n + cols - 1) // cols
    fig = Figure(figsize=(6.2 * cols, 3.8 * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    colors = {
        "ckf": "C0",
        "fkf": "C3",
        "lkf": "C2",
        "dkf": "C6",
        "fkf-feedback": "C1",
        "ldf": "C4",
        "naive": "C5",
    }
    # a line style per method as well: where two methods' means coincide (CKF and FKF at a high p_D), the
    # dashed one stays visible on the solid one
    styles = {"fkf": "--", "lkf": "-.", "dkf": ":", "fkf-feedback": (0, (5, 1)), "ldf": (0, (3, 1, 1, 1))}
    for ax, (title, k, curves) in zip(axes, panels, strict=False):
        for name, (mean, lo, hi) in curves.items():
            c = colors.get(name, None)
            ax.fill_between(k, lo, hi, color=c, alpha=0.15, lw=0)
            ax.plot(k, mean, color=c, lw=1.5, ls=styles.get(name, "-"), label=f"{name.upper()} (mean)")
        if thresholds is not None:
            # log B's label above its line, log A's below its own: never on top of each other, however close
            # the two lines are on the panel's scale; the limits leave room for both labels.
            lo_t, hi_t = min(thresholds), max(thresholds)
            y0, y1 = ax.get_ylim()
            y0, y1 = min(y0, lo_t), max(y1, hi_t)
            pad = 0.09 * (y1 - y0)
            ax.set_ylim(min(y0, lo_t - pad), max(y1, hi_t + pad))
            for v, lab in zip(thresholds, ("log A (delete)", "log B (confirm)"), strict=True):
                above = v == hi_t and lo_t < hi_t
                ax.axhline(v, color="0.4", ls=":", lw=1)
                ax.annotate(
                    lab,
                    (1.0, v),
                    xycoords=("axes fraction", "data"),
                    xytext=(-3, 1.5 if above else -1.5),
                    textcoords="offset points",
                    fontsize="x-small",
                    ha="right",
                    va="bottom" if above else "top",
                    color="0.3",
                )
        ax.set_title(title, fontsize="medium")
        ax.set_xlabel("scan k")
        ax.set_ylabel("log LR(k)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="x-small", loc="best")
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig


def slrt_scan_figure(sensors: np.ndarray, clutter_xy: list[np.ndarray], target_xy: list[np.ndarray],
                     truth: np.ndarray, title: str = "") -> Figure:  # fmt: skip
    """A single scan in Cartesian x–y: radars, each radar's false alarms and target detections, the track."""
    fig = Figure(figsize=(6.4, 6.0), layout="constrained")
    ax = fig.add_subplot()
    for s, (c, t) in enumerate(zip(clutter_xy, target_xy, strict=True)):
        ax.plot(
            c[:, 0] / 1e3, c[:, 1] / 1e3, ".", color=f"C{s}", ms=4, alpha=0.7, label=f"radar {s + 1}: clutter"
        )
        if len(t):
            ax.plot(t[:, 0] / 1e3, t[:, 1] / 1e3, "x", color=f"C{s}", ms=8, mew=2)
    ax.plot(sensors[:, 0] / 1e3, sensors[:, 1] / 1e3, "k^", ms=9, label="radars")
    ax.plot(truth[:, 0] / 1e3, truth[:, 2] / 1e3, "k-", lw=1.2, label="target track (× detections)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [km]")
    ax.set_ylabel("y [km]")
    ax.grid(alpha=0.3)
    fig.legend(fontsize="x-small", loc="outside lower center", ncol=3)  # below the plane: hides no point
    if title:
        ax.set_title(title)
    return fig


def radar_trajectory_figure(t: np.ndarray, x: np.ndarray, r: np.ndarray, y: np.ndarray) -> Figure:
    """The 2-D radar example (the mode-signature paper, §IV.B): the planar path, the reference, and the range/bearing
    measurements mapped back to the plane; right, range and bearing against time.

    Args:
        t: Times (N,).  x: True [x, ẋ, y, ẏ] (N, 4).  r: References [r_x, ṙ_x, r_y, ṙ_y] (N, 4).
        y: Measurements [range, bearing] (N, 2), bearing in radians.
    """
    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.2, 1]})
    mx, my = y[:, 0] * np.cos(y[:, 1]), y[:, 0] * np.sin(y[:, 1])
    ax.plot(mx, my, ".", color="C3", ms=1.5, alpha=0.3, label="measurements (κ cos χ, κ sin χ)")
    ax.plot(r[:, 0], r[:, 2], color="0.6", lw=1, ls="--", label="nominal reference")
    ax.plot(x[:, 0], x[:, 2], color="C0", lw=1.2, label="vehicle")
    ax.plot([0.0], [0.0], "k^", ms=8, label="radar")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize="small", loc="best")
    ax2.plot(t, y[:, 0], color="C0", lw=0.8, label="range κ [m]")
    ax2.set_xlabel("time t [s]")
    ax2.set_ylabel("range [m]", color="C0")
    ax3 = ax2.twinx()
    ax3.plot(t, np.degrees(y[:, 1]), color="C1", lw=0.8)
    ax3.set_ylabel("bearing χ [deg]", color="C1")
    return fig


def maneuver_figure(
    truth: np.ndarray,
    scan: np.ndarray,
    per_sigma: list[tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]],
    *,
    method: str = "IMM",
    model_names: tuple[str, ...] = (),
    events: tuple[int, ...] = (),
) -> Figure:
    """Figs 2–4 of the maneuver paper and the IMM model probabilities, 2×2.

    Args:
        truth: (N, 4) true [x, ẋ, y, ẏ] at scans 1..N.
        scan: (N−2,) scan numbers of the estimates (3..N).
        per_sigma: (σ, track of one run (N−2, 2), ē (N−2, 2), σ̂ (N−2, 2), mean μ (N−2, r) or None).
        events: onset scans of the input changes, drawn as vertical lines.
    """
    fig = Figure(figsize=(12, 8.4), layout="constrained")
    (a2, a3), (a4, a5) = fig.subplots(2, 2)
    a2.plot(truth[:, 0] / 1e3, truth[:, 2] / 1e3, "k-", lw=2.2, label="true track")
    for i, (sigma, track, _, _, _) in enumerate(per_sigma):
        a2.plot(
            track[:, 0] / 1e3,
            track[:, 1] / 1e3,
            color=f"C{i}",
            lw=0.8,
            label=f"{method}, σ = {sigma:g} m (run 1)",
        )
    a2.set_xlabel("x [km]")
    a2.set_ylabel("y [km]")
    a2.set_title("Fig 2: true and filtered tracks", fontsize="medium")
    a2.legend(fontsize="x-small")
    styles = {0: "-", 1: "--"}
    for i, (sigma, _, mean, sd, mu) in enumerate(per_sigma):
        for j, axis in enumerate("xy"):
            c = f"C{2 * i + j}"
            a3.plot(scan, mean[:, j], color=c, lw=0.9, label=f"$\\bar e_{axis}$, σ = {sigma:g}")
            a4.plot(scan, sd[:, j], color=c, lw=0.9, label=f"$\\sigma_{{\\hat {axis}}}$, σ = {sigma:g}")
        if mu is not None:
            for j in range(mu.shape[1]):
                name = model_names[j] if j < len(model_names) else f"model {j + 1}"
                a5.plot(
                    scan,
                    mu[:, j],
                    color=f"C{j}",
                    ls=styles.get(i, ":"),
                    lw=1.0,
                    label=f"μ {name}, σ = {sigma:g}",
                )
    a3.set_title("Fig 3: mean filtering error (eq 14)", fontsize="medium")
    a3.set_ylabel("truth − estimate [m]")
    a4.set_title("Fig 4: filtering-error standard deviation (eq 15)", fontsize="medium")
    a4.set_ylabel("[m]")
    if any(np.any(sd > 0) for _, _, _, sd, _ in per_sigma):
        a4.set_yscale("log")
        lo, hi = a4.get_ylim()
        a4.set_ylim(lo, hi * (hi / lo) ** 0.3)  # a free band above the curves for the legend
    a5.set_title(f"mean {method} model probabilities", fontsize="medium")
    a5.set_ylabel("μ_j(k)")
    if any(mu is not None for *_, mu in per_sigma):
        a5.set_ylim(0, 1.3)  # a free band above μ = 1 for the legend
        a5.set_yticks(np.linspace(0.0, 1.0, 6))
    else:
        a5.set_ylim(0, 1)
    if not any(mu is not None for *_, mu in per_sigma):
        a5.text(
            0.5, 0.5, f"no model probabilities ({method})", ha="center", va="center", transform=a5.transAxes
        )
    for ax in (a3, a4, a5):
        for n in events:
            ax.axvline(n, color="0.6", ls=":", lw=0.8)
        ax.set_xlabel("scan k")
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize="x-small", ncol=2)
    a2.grid(alpha=0.3)
    return fig


def maneuver_comparison_figure(
    scan: np.ndarray,
    rms: dict[tuple[float, str], np.ndarray],
    rate: dict[tuple[float, str], np.ndarray],
    *,
    events: tuple[int, ...] = (),
) -> Figure:
    """Beyond the maneuver paper: RMS position error per method against scan (top, one panel per σ) and the fraction
    of runs declaring a maneuver at each scan (bottom, GLR and MLR)."""
    sigmas = sorted({s for s, _ in rms})
    fig = Figure(figsize=(6.2 * len(sigmas), 7.4), layout="constrained")
    axes = fig.subplots(2, len(sigmas), squeeze=False, sharex=True)
    colors = {"imm": "C0", "glr": "C3", "mlr": "C2", "cv": "0.4"}
    for c, sigma in enumerate(sigmas):
        top, bottom = axes[0, c], axes[1, c]
        for (s, m), y in rms.items():
            if s == sigma:
                top.plot(scan, y, color=colors.get(m), lw=1.0, label=m.upper())
        if any(np.any(y > 0) for (s, _), y in rms.items() if s == sigma):
            top.set_yscale("log")
        for (s, m), y in rate.items():
            if s == sigma:
                bottom.plot(scan, y, color=colors.get(m), lw=0.9, label=m.upper())
        top.set_title(f"RMS position error, σ = {sigma:g} m", fontsize="medium")
        top.set_ylabel("RMS error [m]")
        bottom.set_title("declarations per scan (fraction of runs)", fontsize="medium")
        bottom.set_xlabel("scan k")
        bottom.set_ylabel("fraction of runs")
        for ax in (top, bottom):
            for n in events:
                ax.axvline(n, color="0.6", ls=":", lw=0.8)
            ax.grid(alpha=0.3, which="both")
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize="x-small")
        if not any(s == sigma for s, _ in rate):
            bottom.text(0.5, 0.5, "no GLR / MLR run", ha="center", va="center", transform=bottom.transAxes)
    return fig


def mac_roc_figure(
    panels: list[tuple[float, dict[str, tuple[np.ndarray, np.ndarray]]]],
    title: str = "",
    pf_min: float = 1e-12,
) -> Figure:
    """ATC-10 Figs 3.3–3.6, 3.8: ROC contours, p_f (log) against 1 − p_d (log), one colour per ℓ.

    Args:
        panels: (ℓ, {"upper" | "lower" | "exact" | "gaussian" | "montecarlo": (log10 p_m, log10 p_f)}).
    """
    fig = Figure(figsize=(7.0, 5.0), layout="constrained")
    ax = fig.add_subplot()
    styles = {
        "upper": dict(ls="-", lw=1.5),
        "lower": dict(ls="--", lw=1.2),
        "exact": dict(ls=":", lw=1.8),
        "gaussian": dict(ls="-.", lw=1.3),
        "montecarlo": dict(ls="none", marker="o", ms=3.5),
    }
    names = {
        "upper": "upper bound (3.5.13)",
        "lower": "lower bound (3.5.14)",
        "exact": "exact",
        "gaussian": "ROC$_g$",
        "montecarlo": "Monte Carlo",
    }
    seen: set[str] = set()
    lo_x, lo_y = 1e-5, pf_min
    for i, (ell, curves) in enumerate(panels):
        color = f"C{i % 10}"
        for kind, (lpm, lpf) in curves.items():
            ok = np.isfinite(lpm) & np.isfinite(lpf)
            if not ok.any():
                continue
            label = f"{names[kind]}" if kind not in seen else None
            seen.add(kind)
            lo_x = min(lo_x, float(10.0 ** lpm[ok].min()))
            lo_y = min(lo_y, float(10.0 ** lpf[ok].min()))
            ax.plot(10.0 ** lpm[ok], 10.0 ** lpf[ok], color=color, **styles[kind], label=label)
        ax.plot([], [], color=color, lw=6, alpha=0.5, label=f"ℓ = {ell:.4g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(max(lo_x, 1e-40), 0.6)  # the lower-bound contours reach p_m ~ 1e-20 and beyond
    ax.set_ylim(max(lo_y, 1e-40), 1.5)
    ax.set_xlabel(r"$p_m = 1 - p_d$")
    ax.set_ylabel(r"$p_f$")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small", loc="lower left", ncol=2)
    if title:
        ax.set_title(title)
    return fig


def exponent_figure(
    lines: list[tuple[str, np.ndarray, np.ndarray]], *, vs_n: bool, title: str = ""
) -> Figure:
    """ATC-10 Fig. 3.9 (Exp against N, log axis) or Fig. 3.10 (Exp against Exp_g, with the diagonal)."""
    fig = Figure(figsize=(6.4, 4.4), layout="constrained")
    ax = fig.add_subplot()
    for label, x, y in lines:
        ax.plot(x, y, lw=1.4, label=label)
    if vs_n:
        ax.set_xscale("log")
        ax.set_xlabel("N")
        top = max(float(np.max(y)) for _, _, y in lines)
        ax.set_ylim(0, max(top * 1.05, 1e-9))
    else:
        xmax = max(float(np.max(x)) for _, x, _ in lines)
        ax.plot([0, xmax], [0, xmax], color="0.4", ls=":", lw=1, label="Exp = Exp$_g$ (N = ∞)")
        ax.set_xlabel("Exp$_g$")
    ax.set_ylabel("Exp")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return fig


def density_figure(
    curves: list[tuple[str, str, np.ndarray, np.ndarray, np.ndarray | None]], b: float
) -> Figure:
    """ATC-10 Fig. 3.2: the amplitude densities at equal second moment (impulses drawn as arrows)."""
    fig = Figure(figsize=(6.4, 4.2), layout="constrained")
    ax = fig.add_subplot()
    top = 0.0
    for i, (rid, name, x, pdf, w) in enumerate(curves):
        if w is None:
            ax.plot(x, pdf, color=f"C{i}", lw=1.5, label=f"{rid} {name}")
            top = max(top, float(np.max(pdf)))
    for i, (rid, name, x, _pdf, w) in enumerate(curves):
        if w is not None:
            for xi, wi in zip(x, w, strict=True):
                ax.annotate(
                    "", (xi, 1.1 * top), (xi, 0.0), arrowprops=dict(arrowstyle="->", color=f"C{i}", lw=1.8)
                )
                ax.annotate(f"{wi:g}", (xi, 1.12 * top), ha="center", fontsize="small", color=f"C{i}")
            ax.plot([], [], color=f"C{i}", lw=1.8, label=f"{rid} {name} (impulses)")
    ax.set_ylim(0, 1.25 * top)
    ax.set_xlabel("x")
    ax.set_ylabel("C(x)")
    ax.set_title(f"amplitude densities, b = {b:.4g}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return fig


def schematic_figure(t: np.ndarray, n: np.ndarray) -> Figure:
    """ATC-10 Fig. 3.7: the MAN component implied by the quasi-optimal density, ±A over 2τ."""
    fig = Figure(figsize=(6.0, 3.2), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(t, n, color="C0", lw=1.6, label="$+A$")
    ax.plot(t, -n, color="C1", lw=1.6, ls="--", label="$-A$")
    ax.set_xlabel(r"$(t - t_j)/\tau$")
    ax.set_ylabel(r"$n_{ij}(t)$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return fig


def autocorrelation_figure(lines: list[tuple[str, np.ndarray, np.ndarray]]) -> Figure:
    """ATC-10 Fig. 3.11: aperiodic autocorrelations of PSK codes beside the ideal triangle."""
    fig = Figure(figsize=(6.8, 4.0), layout="constrained")
    ax = fig.add_subplot()
    span = max(float(np.max(np.abs(t))) for _, t, _ in lines)
    for label, t, R in lines:
        ax.plot(t, R, lw=1.2, label=label)
    tt = np.linspace(-span, span, 4001)
    ax.plot(tt, np.clip(1.0 - np.abs(tt), 0.0, None), color="k", ls=":", lw=1.2, label="ideal triangle")
    ax.set_xlabel(r"$t/\tau_c$")
    ax.set_ylabel("R(t)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return fig


def calibration_roc_figure(
    panels: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]], pfa: float, title: str = ""
) -> Figure:
    """Empirical ROC curves of the test max Λ > t (``detect --calibrate``): one panel per ANR, one line per
    horizon; the dashed line marks the calibrated P_FA.

    Args:
        panels: panel title → {line label → (P_FA, P_D)}.
    """
    fig = Figure(figsize=(3.6 * len(panels), 3.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(panels), sharey=True, squeeze=False)).ravel()
    for ax, (name, lines) in zip(axes, panels.items(), strict=True):
        for label, (pf, pd) in lines.items():
            ax.step(np.maximum(pf, 1e-6), pd, where="post", lw=1, label=label)
        ax.axvline(pfa, color="k", ls="--", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlim(max(1e-4, 0.2 / max(len(next(iter(lines.values()))[0]), 1)), 1.0)
        ax.set_ylim(-0.02, 1.02)
        ax.set_title(name, fontsize="medium")
        ax.set_xlabel("$P_{FA}$ (no signature)")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("$P_D$ (max Λ > t)")
    axes[0].legend(title="horizon", fontsize="small", loc="lower right")  # below an ROC's curves: empty
    if title:
        fig.suptitle(title)
    return fig


def maneuver_record_figure(
    z: np.ndarray,
    scan: np.ndarray,
    first: int,
    tracks: dict[str, np.ndarray],
    speeds: dict[str, np.ndarray],
    declarations: dict[str, list[tuple[int, int]]],
    mu: np.ndarray | None = None,
    model_names: tuple[str, ...] = (),
    title: str = "",
) -> Figure:
    """One track record through the trackers of the maneuver paper: the measured positions and each method's
    track in the plane (left, GLR/MLR declarations as ▲ on the track); against scan (right) the estimated
    speed, the declarations (one row per method: ▲ at the declaration scan, a bar back to the estimated
    onset) with the missed scans, and the IMM model probabilities.

    Args:
        z: (K, 2) measured positions [m] of the grid scans (NaN: missed).
        scan: (K,) scan numbers of the grid.
        first: grid index of the first tracked scan (tracks[m][i] is grid scan first + i).
        tracks, speeds: method → (K − first, 2) positions [m] and (K − first,) speeds [m/s].
        declarations: method → [(grid index of the declaration, grid index of the estimated onset)].
        mu: (K − first, r) IMM model probabilities, or None.
    """
    fig = Figure(figsize=(13, 7), layout="constrained")
    gs = fig.add_gridspec(3, 2, width_ratios=(1.1, 1.0), height_ratios=(3.0, 1.4, 2.2))
    ax = fig.add_subplot(gs[:, 0])
    a_v = fig.add_subplot(gs[0, 1])
    a_d = fig.add_subplot(gs[1, 1], sharex=a_v)
    a_mu = fig.add_subplot(gs[2, 1], sharex=a_v)
    ok = ~np.any(np.isnan(z), axis=1)
    ax.plot(z[ok, 0] / 1e3, z[ok, 1] / 1e3, ".", color="0.55", ms=3, label="measured")
    k_tr = scan[first:]
    colors = {m: f"C{i}" for i, m in enumerate(tracks)}
    for m, pos in tracks.items():
        ax.plot(pos[:, 0] / 1e3, pos[:, 1] / 1e3, color=colors[m], lw=1.0, label=m)
        a_v.plot(k_tr, speeds[m], color=colors[m], lw=0.9, label=m)
    rows = [*declarations, "missed"]
    for row, m in enumerate(declarations):
        decl = declarations[m]
        if not decl:
            continue
        g = np.array([d[0] for d in decl])
        n = np.array([d[1] for d in decl])
        p = tracks[m][g - first]
        ax.plot(p[:, 0] / 1e3, p[:, 1] / 1e3, "^", color=colors[m], mec="k", mew=0.5, ms=6,
                label=f"{m} declarations ({g.size})")  # fmt: skip
        a_d.hlines(np.full(g.size, row), scan[n], scan[g], color=colors[m], lw=2.0, alpha=0.6)
        a_d.plot(scan[g], np.full(g.size, row), "^", color=colors[m], mec="k", mew=0.5, ms=6)
    missed = scan[~ok]
    a_d.plot(missed, np.full(missed.size, len(rows) - 1), "|", color="0.4", ms=8)
    a_d.set_yticks(range(len(rows)), [*(f"{m}" for m in declarations), f"missed ({missed.size})"])
    a_d.set_ylim(-0.7, len(rows) - 0.3)
    a_d.invert_yaxis()
    a_d.set_title("declarations (▲; bar: back to the estimated onset) and missed scans", fontsize="medium")
    ax.set_xlabel("x [km]")
    ax.set_ylabel("y [km]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("measured positions and tracks", fontsize="medium")
    ax.legend(fontsize="x-small")
    a_v.set_ylabel("speed [m/s]")
    a_v.set_title("estimated speed", fontsize="medium")
    a_v.legend(fontsize="x-small", ncol=2)
    if mu is not None:
        for j in range(mu.shape[1]):
            name = model_names[j] if j < len(model_names) else f"model {j + 1}"
            a_mu.plot(k_tr, mu[:, j], color=f"C{j}", lw=1.0, label=f"μ {name}")
        a_mu.legend(fontsize="x-small", ncol=3)
    else:
        a_mu.text(0.5, 0.5, "no IMM among the methods", ha="center", va="center", transform=a_mu.transAxes)
    a_mu.set_ylim(0, 1)
    a_mu.set_ylabel("μ_j(k)")
    a_mu.set_xlabel("scan k")
    a_mu.set_title("IMM model probabilities", fontsize="medium")
    for a in (ax, a_v, a_d, a_mu):
        a.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig


def ebpsk_waveform_figure(
    t: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    bits: np.ndarray,
    symbol_s: float,
    f: np.ndarray,
    h: np.ndarray,
    f_if: float,
    *,
    title: str = "",
) -> Figure:
    """EBPSK (Yao, Teng & Wu's front end): the bits, the IF waveform, the impacting filter's output and
    the filter's magnitude response |H(f)| with the carrier marked, stacked."""
    fig = Figure(figsize=(8, 7), layout="constrained")
    axes = fig.subplots(4, 1)
    edges = np.arange(len(bits) + 1) * symbol_s * 1e9
    axes[0].stairs(bits, edges, color="C0", baseline=None)
    axes[0].set_ylabel("bit")
    axes[0].set_ylim(-0.2, 1.2)
    axes[1].plot(t * 1e9, x, color="C1", lw=0.8)
    axes[1].set_ylabel("IF waveform x")
    axes[2].plot(t * 1e9, y, color="C2", lw=0.8)
    axes[2].set_ylabel("filter output y")
    axes[2].set_xlabel("time t [ns]")
    for ax in axes[:3]:
        for e in edges:
            ax.axvline(e, color="0.8", lw=0.5)
        ax.set_xlim(edges[0], edges[-1])
    mag = 20 * np.log10(np.maximum(np.abs(h), 1e-12))
    axes[3].plot(f / 1e6, mag, color="C3")
    axes[3].axvline(f_if / 1e6, color="k", ls=":", lw=0.8, label=f"f_if = {f_if / 1e6:g} MHz")
    axes[3].set_ylim(max(-80.0, float(mag.min())), 3)
    axes[3].set_xlabel("frequency f [MHz]")
    axes[3].set_ylabel("|H(f)| [dB]")
    axes[3].legend(fontsize="small", loc="lower right")
    for ax in axes:
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig


def ebpsk_ber_figure(
    ebn0_db: np.ndarray,
    curves: Sequence[tuple[str, np.ndarray, np.ndarray]],
    bound: np.ndarray,
    *,
    closed_forms: Sequence[tuple[str, np.ndarray]] = (),
    title: str = "",
) -> Figure:
    """BER of EBPSK receivers against E_b/N_0: each of ``curves`` (label, BER, SE) with ±2 SE bars (zero
    counts not drawn), each of ``closed_forms`` (label, BER) as a thin line, beside the coherent bound
    Q(√((1 − ρ) E_b/N_0))."""
    fig = Figure(figsize=(7, 4.5), layout="constrained")
    ax = fig.add_subplot()
    for label, ber, se in curves:
        ber, se = np.asarray(ber), np.asarray(se)
        ok = ber > 0
        ax.errorbar(ebn0_db[ok], ber[ok], yerr=2 * se[ok], marker="o", ms=4, capsize=2, label=label)
    for label, ber in closed_forms:
        ax.semilogy(ebn0_db, ber, ":", lw=1, label=label)
    ax.semilogy(ebn0_db, bound, "k--", lw=1, label=r"coherent bound $Q(\sqrt{(1-\rho)E_b/N_0})$")
    ax.set_xlabel(r"$E_b/N_0$ [dB]")
    ax.set_ylabel("bit error rate")
    ax.set_yscale("log")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title, fontsize="medium")
    return fig


def ebpsk_front_end_figure(
    scan: np.ndarray,
    range_km: np.ndarray,
    enr_db: np.ndarray,
    pd: np.ndarray,
    sigma_range: np.ndarray,
    sigma_cross: np.ndarray,
    sigma_pos: np.ndarray,
    sigma_paper: tuple[float, ...] = (100.0, 200.0),
    *,
    title: str = "",
) -> Figure:
    """What the EBPSK front end delivers along the track: range and E/N_0, P_D, and the range, cross-range and
    position σ beside the paper's constant σ values."""
    fig = Figure(figsize=(8, 8), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    axes[0].plot(scan, range_km, color="C0")
    axes[0].set_ylabel("range [km]", color="C0")
    twin = axes[0].twinx()
    twin.plot(scan, enr_db, color="C1")
    twin.set_ylabel(r"$E/N_0$ [dB]", color="C1")
    axes[1].plot(scan, pd, color="C2")
    axes[1].set_ylim(-0.02, 1.02)
    axes[1].set_ylabel(r"$P_D$")
    axes[2].semilogy(scan, sigma_pos, color="C3", label=r"position $\sigma$ (per axis)")
    axes[2].semilogy(scan, sigma_cross, color="C4", ls="--", lw=1, label=r"cross-range $r\sigma_\varphi$")
    axes[2].semilogy(scan, sigma_range, color="C5", ls=":", lw=1, label=r"range $\sigma_r$")
    for i, s in enumerate(sigma_paper):
        axes[2].axhline(
            s, color=("k", "0.5")[i % 2], ls=(0, (4, 2 + 2 * i)), lw=0.9, label=f"paper σ = {s:g} m"
        )
    axes[2].set_ylabel(r"$\sigma$ [m]")
    axes[2].set_xlabel("scan k")
    axes[2].legend(fontsize="small", ncol=2)
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig
