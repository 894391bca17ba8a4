"""Figure builders (the only module that imports matplotlib). Each returns a ``Figure``; no pyplot."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from motionsig_cli.signals.signature import Signature


def signature_figure(sig: Signature, *, title: str = "", theta: float = 0.0, f_c: float = 1.0) -> Figure:
    """Chips p_k[τ], carrier cos(2π f_c t_k + θ) and signature z_k (seed 000 eqs 1–3), stacked."""
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
    axes[2].legend(loc="upper right", fontsize="small")
    for ax in axes:
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    return fig


def correlation_figure(lags: np.ndarray, values: np.ndarray, labels: list[str], bound: int | None) -> Figure:
    """Periodic correlation R[ℓ] against lag for a few code pairs, with ±t(n) lines."""
    fig = Figure(figsize=(8, 3.5), layout="constrained")
    ax = fig.add_subplot()
    for v, lab in zip(values, labels, strict=True):
        ax.plot(lags, v, marker=".", lw=0.8, label=lab)
    if bound is not None:
        for y in (-bound, bound - 2):
            ax.axhline(y, color="k", lw=0.6, ls=":")
    ax.set_xlabel("lag ℓ [chips]")
    ax.set_ylabel("periodic correlation R[ℓ]")
    ax.legend(fontsize="small", ncol=2)
    ax.grid(alpha=0.3)
    return fig
