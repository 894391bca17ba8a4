"""``motionsig simulate``: the closed-loop vehicle carrying a mode signature (seed 000 §IV.A, Fig 2)."""

from __future__ import annotations

import math
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from motionsig_cli.cli.common import (
    DEFAULT_SEED_VALUE,
    CodesVariant,
    DebugOpt,
    FormatOpt,
    OutOpt,
    OutputFormat,
    PlotOpt,
    QuietOpt,
    SeedOpt,
    check_outputs,
    checked,
    float_list,
    note,
    save_figure,
)
from motionsig_cli.cli.io import Table, emit, make_meta
from motionsig_cli.experiments.lmp1d import TrialDraw, anr_db, draw_trial, signature_batch
from motionsig_cli.models.vehicle import Vehicle1D, nominal_reference, pole_placement_gain, simulate_1d
from motionsig_cli.models.vehicle2d import SEED_ANR_PAIRS, Vehicle2D, anr_pair_variances, simulate_2d
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import table1_codes

MAX_RECORD = 1_000_000  # samples per simulated record


class Example(StrEnum):
    """Which example of seed 000."""

    one_d = "1d"
    two_d = "2d"


class SigAxes(StrEnum):
    """Axes of the 2-D vehicle whose reference carries the signature."""

    both = "both"
    x = "x"
    y = "y"


class DbConvention(StrEnum):
    """How an ANR given in dB is read."""

    paper_ln = "paper-ln"
    log10 = "log10"


def resolve_R(R: float | None, anr_db_value: float | None, convention: DbConvention, a_sig: float) -> float:
    """Measurement variance from --R or --anr-db (ANR = a²/(2R), eq 58; 'paper-ln' reads dB as 10·ln)."""
    if R is not None and anr_db_value is not None:
        raise typer.BadParameter("give --R or --anr-db, not both", param_hint="--anr-db")
    if anr_db_value is not None:
        anr = (
            math.exp(anr_db_value / 10) if convention is DbConvention.paper_ln else 10 ** (anr_db_value / 10)
        )
        R = a_sig**2 / (2 * anr)
    R = 1e-5 if R is None else R
    if not (math.isfinite(R) and R > 0):
        raise typer.BadParameter(f"measurement variance must be > 0, got {R}", param_hint="--R")
    return R


def resolve_K(K: str | None, wn: float, zeta: float, T: float) -> tuple[float, float]:
    """Gain from --K k1,k2 or by pole placement (spec §1.8)."""
    if K is not None:
        vals = checked("--K", float_list, K, what="gain")
        if len(vals) != 2:
            raise typer.BadParameter(f"expected two gains k1,k2, got {len(vals)}", param_hint="--K")
        return vals[0], vals[1]
    return checked("--pole-wn/--pole-zeta", pole_placement_gain, T, wn, zeta)


def simulate(
    example: Annotated[
        Example,
        typer.Option(
            "--example",
            help="1d: point mass, position measured (eqs 53-55); 2d: planar vehicle, radar range/bearing (eqs 59-60).",
        ),
    ] = Example.one_d,
    mode: Annotated[
        int | None, typer.Option("--mode", help="Table I mode 1-3; default drawn from --seed.")
    ] = None,
    tau: Annotated[
        int | None, typer.Option("--tau", help="Code phase in samples; default drawn on the chip grid.")
    ] = None,
    tau_chips: Annotated[
        int | None, typer.Option("--tau-chips", help="Code phase in chips (tau = chips * m_rho).")
    ] = None,
    theta: Annotated[
        str, typer.Option("--theta", help="Carrier phase [rad] or 'random' (from --seed).")
    ] = "random",
    a_sig: Annotated[float, typer.Option("--a-sig", help="Signature amplitude a_sig (seed: 0.5).")] = 0.5,
    a_r: Annotated[float, typer.Option("--a-r", help="Nominal reference amplitude (seed: 10).")] = 10.0,
    f_r: Annotated[
        float, typer.Option("--f-r", help="Nominal reference frequency [Hz] (seed: 0.01, 0.1, 1).")
    ] = 0.01,
    fc: Annotated[float, typer.Option("--fc", help="Carrier frequency f_c [Hz].")] = 1.0,
    T: Annotated[float, typer.Option("--T", help="Sample interval [s] (assumption).")] = 0.05,
    mrho: Annotated[int, typer.Option("--mrho", help="Samples per chip (assumption).")] = 20,
    K: Annotated[str | None, typer.Option("--K", help="Feedback gain k1,k2; default pole placement.")] = None,
    pole_wn: Annotated[float, typer.Option("--pole-wn", help="Pole-placement natural frequency [rad/s].")] = 4
    * math.pi,
    pole_zeta: Annotated[float, typer.Option("--pole-zeta", help="Pole-placement damping ratio.")] = 0.7,
    sigma_a: Annotated[
        float, typer.Option("--sigma-a", help="True white-acceleration noise [m/s^2] (assumption).")
    ] = 0.01,
    R: Annotated[
        float | None, typer.Option("--R", help="1d: measurement-noise variance (default 1e-5).")
    ] = None,
    R_range: Annotated[
        float | None, typer.Option("--R-range", help="2d: range-noise variance [m^2].")
    ] = None,
    R_bearing: Annotated[
        float | None, typer.Option("--R-bearing", help="2d: bearing-noise variance [rad^2].")
    ] = None,
    anr_pair: Annotated[
        int | None,
        typer.Option(
            "--anr-pair",
            help="2d: Fig 7's (angle, range) ANR pair 1-4 = (9.2, 37.1) ... (101.3, 129.2); default 4.",
        ),
    ] = None,
    start: Annotated[
        str, typer.Option("--start", help="2d: initial position x,y [m] (seed: 70,-20); zero velocity.")
    ] = "70,-20",
    sig_axes: Annotated[
        SigAxes, typer.Option("--sig-axes", help="2d: axes whose reference carries the signature.")
    ] = SigAxes.both,
    anr_db_value: Annotated[float | None, typer.Option("--anr-db", help="ANR in dB instead of --R.")] = None,
    db_convention: Annotated[
        DbConvention, typer.Option("--db-convention", help="paper-ln: seed's 10*ln; log10: true decibels.")
    ] = DbConvention.paper_ln,
    duration: Annotated[float, typer.Option("--duration", help="Record length [s].")] = 80.0,
    codes: Annotated[
        CodesVariant, typer.Option("--codes", help="Table I codes: corrected or printed.")
    ] = CodesVariant.corrected,
    no_signature: Annotated[bool, typer.Option("--no-signature", help="Simulate H0 (no signature).")] = False,
    zdot: Annotated[
        str,
        typer.Option(
            "--zdot", help="Signature derivative in the velocity reference: analytic or finite-difference."
        ),
    ] = "analytic",
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    plot: PlotOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Closed-loop vehicle whose position reference carries a mode signature: 1-D (eqs 53-55, Fig 2) or 2-D radar (eqs 59-60).

    The random inputs are those of Monte Carlo trial 0 of `detect --montecarlo --seed SEED`.

    \b
    Example:
      motionsig simulate --mode 2 --tau-chips 5 --R 1e-3 --plot fig2.png | motionsig detect
      motionsig simulate --anr-db 48.3 --f-r 0.1 -o run.csv
      motionsig simulate --example 2d --anr-pair 3 --plot traj.png | motionsig detect
    """
    check_outputs(out, plot)
    if example is Example.one_d:
        for opt, val in (("--R-range", R_range), ("--R-bearing", R_bearing), ("--anr-pair", anr_pair)):
            if val is not None:
                raise typer.BadParameter("applies to --example 2d only", param_hint=opt)
        if start != "70,-20" or sig_axes is not SigAxes.both:
            raise typer.BadParameter("applies to --example 2d only", param_hint="--start/--sig-axes")
    else:
        for opt, val in (("--R", R), ("--anr-db", anr_db_value)):
            if val is not None:
                raise typer.BadParameter(
                    "applies to --example 1d; use --R-range/--R-bearing or --anr-pair", param_hint=opt
                )
    if mode is not None and mode not in (1, 2, 3):
        raise typer.BadParameter(f"Table I has modes 1, 2, 3; got {mode}", param_hint="--mode")
    for opt, val in (("--tau", tau), ("--tau-chips", tau_chips)):
        if val is not None and abs(val) > 2**40:
            raise typer.BadParameter(f"|code phase| must be <= 2^40, got {val}", param_hint=opt)
    if tau is not None and tau_chips is not None:
        raise typer.BadParameter("give --tau or --tau-chips, not both", param_hint="--tau-chips")
    if not (math.isfinite(duration) and duration > 0):
        raise typer.BadParameter(f"must be > 0, got {duration}", param_hint="--duration")
    for opt, val in (
        ("--T", T),
        ("--fc", fc),
        ("--a-sig", a_sig),
        ("--a-r", a_r),
        ("--f-r", f_r),
        ("--sigma-a", sigma_a),
    ):
        if not (math.isfinite(val) and val >= 0) or (opt == "--T" and val <= 0):
            raise typer.BadParameter(
                f"must be {'> 0' if opt == '--T' else '>= 0'} and finite, got {val}", param_hint=opt
            )
    if mrho < 1:
        raise typer.BadParameter(f"must be >= 1, got {mrho}", param_hint="--mrho")
    gains = resolve_K(K, pole_wn, pole_zeta, T)
    n = round(duration / T)
    if n > MAX_RECORD:
        raise typer.BadParameter(
            f"{n} samples > {MAX_RECORD}: shorten --duration or lengthen --T", param_hint="--duration"
        )
    chips = to_bipolar(table1_codes(codes.value)).astype(float)
    draw = draw_trial(
        seed, 0, n, chips.shape[0], chips.shape[1], mrho, dims=2 if example is Example.two_d else 1
    )
    mode0 = draw.mode if mode is None else mode - 1
    tau0 = tau if tau is not None else tau_chips * mrho if tau_chips is not None else draw.tau
    if theta.strip().lower() == "random":
        th = draw.theta
    else:
        th = checked("--theta", float, theta)
        if not math.isfinite(th):
            raise typer.BadParameter("must be finite or 'random'", param_hint="--theta")
    if zdot not in ("analytic", "finite-difference"):
        raise typer.BadParameter(f"expected analytic or finite-difference, got {zdot!r}", param_hint="--zdot")
    common = dict(
        mode=mode0 + 1,
        tau=int(tau0),
        tau_chips=tau0 / mrho,
        theta=th,
        signature=not no_signature,
        a_sig=a_sig,
        a_r=a_r,
        f_r=f_r,
        f_c=fc,
        f_d=0.0,
        T=T,
        m_rho=mrho,
        n_rho=int(chips.shape[1]),
        K=list(gains),
        sigma_a=sigma_a,
    )
    if example is Example.two_d:
        pair_used = (
            anr_pair if anr_pair is not None else (4 if R_range is None and R_bearing is None else None)
        )
        vehicle2 = _vehicle_2d(
            T, gains, a_sig, a_r, f_r, sigma_a, R_range, R_bearing, anr_pair, start, sig_axes
        )
        _simulate_2d(
            vehicle2, chips, draw, mode0, tau0, th, fc, mrho, n, zdot, no_signature, common,
            codes.value, pair_used, seed, plot, fmt, out, quiet,
        )  # fmt: skip
        return
    Rv = resolve_R(R, anr_db_value, db_convention, a_sig)
    vehicle = checked("--R", Vehicle1D, T=T, K=gains, a_sig=a_sig, a_r=a_r, f_r=f_r, sigma_a=sigma_a, R=Rv)
    z, zd = signature_batch(chips, np.array([mode0]), np.array([tau0]), np.array([th]), fc, T, mrho, n, zdot)
    if no_signature:
        z, zd = np.zeros_like(z), np.zeros_like(zd)
    sim = simulate_1d(vehicle, z, zd, draw.w[None, :], draw.v[None, :])
    anr_lin, anr_log10, anr_ln = anr_db(Rv, a_sig)
    meta = make_meta(
        "simulate",
        example=example.value,
        **common,
        R=Rv,
        anr_linear=anr_lin,
        anr_db_log10=anr_log10,
        anr_db_paper_ln=anr_ln,
        duration=n * T,
        n_samples=n,
        codes=codes.value,
        feedback="true state",
        zdot=zdot,
        seed=seed,
        trial=0,
        assumptions="T, m_rho, K (pole placement wn=4pi, zeta=0.7), sigma_a, x0=0, sine reference: spec section 1.8",
    )
    x = sim["x"][0]
    r = nominal_reference(vehicle, sim["t"])
    cols = ("k", "t", "y", "x", "xdot", "r", "rdot", "z", "zdot", "u")
    rows = [
        (
            k,
            float(sim["t"][k]),
            float(sim["y"][0, k]),
            float(x[k, 0]),
            float(x[k, 1]),
            float(r[k, 0]),
            float(r[k, 1]),
            float(z[0, k]),
            float(zd[0, k]),
            float(sim["u"][0, k]),
        )
        for k in range(n)
    ]
    if plot is not None:
        from motionsig_cli.plotting import response_figure

        save_figure(response_figure(sim["t"], x[:, 0], r[:, 0], r[:, 0] + a_sig * z[0], sim["y"][0]), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(
        f"simulated {n} samples: mode {mode0 + 1}, tau {tau0} samples, theta {th:.3f} rad, R {Rv:g} "
        f"(ANR {anr_lin:.4g} = {anr_log10:.1f} dB; seed's 10*ln label {anr_ln:.1f})",
        quiet,
    )


def _vehicle_2d(
    T: float,
    gains: tuple[float, float],
    a_sig: float,
    a_r: float,
    f_r: float,
    sigma_a: float,
    R_range: float | None,
    R_bearing: float | None,
    anr_pair: int | None,
    start: str,
    sig_axes: SigAxes,
) -> Vehicle2D:
    """The 2-D vehicle from the options (noise from --anr-pair, default 4, or --R-range/--R-bearing)."""
    if anr_pair is not None and (R_range is not None or R_bearing is not None):
        raise typer.BadParameter(
            "give --anr-pair or --R-range/--R-bearing, not both", param_hint="--anr-pair"
        )
    if anr_pair is not None and anr_pair not in (1, 2, 3, 4):
        raise typer.BadParameter(f"Fig 7 has pairs 1-4, got {anr_pair}", param_hint="--anr-pair")
    pr, pb = (
        checked("--a-sig", anr_pair_variances, anr_pair or 4, a_sig)
        if R_range is None or R_bearing is None
        else (0, 0)
    )
    Rr = pr if R_range is None else R_range
    Rb = pb if R_bearing is None else R_bearing
    for opt, val in (("--R-range", Rr), ("--R-bearing", Rb)):
        if not (math.isfinite(val) and val > 0):
            raise typer.BadParameter(f"must be > 0 and finite, got {val}", param_hint=opt)
    xy = checked("--start", float_list, start, what="coordinate")
    if len(xy) != 2:
        raise typer.BadParameter(f"expected x,y, got {len(xy)} numbers", param_hint="--start")
    return checked(
        "--start",
        Vehicle2D,
        T=T,
        K=gains,
        a_sig=a_sig,
        a_r=a_r,
        f_r=f_r,
        sigma_a=sigma_a,
        R_range=Rr,
        R_bearing=Rb,
        start=(xy[0], xy[1]),
        sig_axes=sig_axes.value,
    )


def _simulate_2d(
    vehicle: Vehicle2D,
    chips: np.ndarray,
    draw: TrialDraw,
    mode0: int,
    tau0: int,
    th: float,
    fc: float,
    mrho: int,
    n: int,
    zdot: str,
    no_signature: bool,
    common: dict[str, Any],
    codes: str,
    anr_pair: int | None,
    seed: int,
    plot: Path | None,
    fmt: OutputFormat,
    out: Path | None,
    quiet: bool,
) -> None:
    """The 2-D radar example (eqs 59-60): trajectory and range/bearing record."""
    z, zd = signature_batch(
        chips, np.array([mode0]), np.array([tau0]), np.array([th]), fc, vehicle.T, mrho, n, zdot
    )
    if no_signature:
        z, zd = np.zeros_like(z), np.zeros_like(zd)
    sim = simulate_2d(vehicle, z, zd, draw.w[None], draw.v[None])
    x, y, u, r = sim["x"][0], sim["y"][0], sim["u"][0], sim["r"]
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise typer.BadParameter("the simulation overflowed (non-finite state)", param_hint="--K/--sigma-a")
    near = 10 * math.sqrt(vehicle.R_range)
    true_range = np.hypot(x[:, 0], x[:, 2])
    if true_range.min() <= near:
        k = int(np.argmin(true_range))
        raise typer.BadParameter(
            f"the vehicle passes within {true_range.min():.3g} m of the radar at t = {k * vehicle.T:g} s "
            f"(10 range-noise standard deviations: {near:.3g} m): the bearing is undefined there; move --start or lower --R-range",
            param_hint="--start/--R-range",
        )
    if np.any(y[:, 0] <= 0):
        k = int(np.flatnonzero(y[:, 0] <= 0)[0])
        raise typer.BadParameter(
            f"a measured range is <= 0 (t = {k * vehicle.T:g} s): the range noise exceeds the range; lower it",
            param_hint="--R-range",
        )
    anr_angle, anr_range = vehicle.anr
    meta = make_meta(
        "simulate",
        example="2d",
        **common,
        R_range=vehicle.R_range,
        R_bearing=vehicle.R_bearing,
        anr_pair=anr_pair,
        seed_anr_pair_labels=None if anr_pair is None else list(SEED_ANR_PAIRS[anr_pair - 1]),
        anr_angle_linear=anr_angle,
        anr_angle_db_paper_ln=10 * math.log(anr_angle) if anr_angle > 0 else None,
        anr_angle_db_log10=10 * math.log10(anr_angle) if anr_angle > 0 else None,
        anr_range_linear=anr_range,
        anr_range_db_paper_ln=10 * math.log(anr_range) if anr_range > 0 else None,
        anr_range_db_log10=10 * math.log10(anr_range) if anr_range > 0 else None,
        start=list(vehicle.start),
        sig_axes=vehicle.sig_axes,
        bearing_unit="rad",
        radar="origin",
        duration=n * vehicle.T,
        n_samples=n,
        codes=codes,
        feedback="true state",
        zdot=zdot,
        seed=seed,
        trial=0,
        assumptions=(
            "T, m_rho, K (same on both axes), sigma_a, references x0/y0 + a_r sin(2 pi f_r t), "
            "signature on --sig-axes with a_x = a_y = a_sig, R_range from the printed range label: spec section 1.7"
        ),
    )
    cols = (
        "k", "t", "range", "bearing", "x", "xdot", "y", "ydot",
        "r_x", "rdot_x", "r_y", "rdot_y", "z", "zdot", "u_x", "u_y",
    )  # fmt: skip
    rows = [
        (k, float(sim["t"][k]), *(float(v) for v in (*y[k], *x[k], *r[k], z[0, k], zd[0, k], *u[k])))
        for k in range(n)
    ]
    if plot is not None:
        from motionsig_cli.plotting import radar_trajectory_figure

        save_figure(radar_trajectory_figure(sim["t"], x, r, y), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(
        f"simulated {n} samples (2-D radar): mode {mode0 + 1}, tau {tau0} samples, theta {th:.3f} rad, "
        f"R_range {vehicle.R_range:.3g} m^2, R_bearing {vehicle.R_bearing:.3g} rad^2 "
        + (
            f" (seed's 10*ln ANR: angle {10 * math.log(anr_angle):.1f}, range {10 * math.log(anr_range):.1f})"
            if anr_angle > 0
            else ""
        ),
        quiet,
    )
