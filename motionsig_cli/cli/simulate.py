"""``motionsig simulate``: the closed-loop vehicle carrying a mode signature, after §IV.A (Fig 2) and §IV.B of
the mode-signature paper (47th IEEE CDC, Cancún, 2008).

The command parses the options, builds the vehicle and record configurations (which check every value)
and writes the table of :func:`motionsig_cli.modesig.vehicle_record.simulate_record`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, SeedOpt, choices, command

if TYPE_CHECKING:
    from motionsig_cli.tables import Table

Example = choices("Example", "Which example of the mode-signature paper.", one_d="1d", two_d="2d")
SigAxes = choices(
    "SigAxes", "Axes of the 2-D vehicle whose reference carries the signature.", "both", "x", "y"
)
Feedback = choices(
    "Feedback",
    "What the vehicle's controller feeds back (eq 5).",
    "true",
    "estimate",
)
DbConvention = choices(
    "DbConvention",
    "How an ANR (signature-amplitude-to-noise ratio) given in dB is read.",
    "log10",
    "paper-ln",
)


ExampleOpt = Annotated[
    Example,
    typer.Option(
        "--example",
        help="1d: point mass, position measured (eqs 53-55); "
        "2d: planar vehicle, radar range/bearing (eqs 59-60).",
    ),
]
ModeOpt = Annotated[int | None, typer.Option("--mode", help="Table I mode 1-3; default drawn from --seed.")]
TauOpt = Annotated[
    int | None, typer.Option("--tau", help="Code phase in samples; default drawn on the chip grid.")
]
TauChipsOpt = Annotated[
    int | None, typer.Option("--tau-chips", help="Code phase in chips (tau = chips * m_rho).")
]
ThetaOpt = Annotated[str, typer.Option("--theta", help="Carrier phase [rad] or 'random' (from --seed).")]
ASigOpt = Annotated[float, typer.Option("--a-sig", help="Signature amplitude a_sig (the paper: 0.5).")]
AROpt = Annotated[float, typer.Option("--a-r", help="Nominal reference amplitude (the paper: 10).")]
FROpt = Annotated[
    float, typer.Option("--f-r", help="Nominal reference frequency [Hz] (the paper: 0.01, 0.1, 1).")
]
FcOpt = Annotated[float, typer.Option("--fc", help="Carrier frequency f_c [Hz].")]
FdOpt = Annotated[
    float | None,
    typer.Option(
        "--f-d",
        help="Carrier offset f_d [Hz] of the received signature (eq 3: cos(2 pi (f_c + f_d) t + theta)); "
        "default 0, as in the paper. The detector does not assume it: search it with --fc-grid or --fd-grid.",
    ),
]
FeedbackOpt = Annotated[
    Feedback | None,
    typer.Option(
        "--feedback",
        help="1d: the controller on the true state (true, eq 44; the default) or on the vehicle's own "
        "estimate (estimate, eq 5: a Kalman filter of its own position sensor, noise R, assumed).",
    ),
]
TOpt = Annotated[
    float, typer.Option("--T", help="Sample interval [s] (assumed; the paper does not state it).")
]
MrhoOpt = Annotated[
    int, typer.Option("--mrho", help="Samples per chip (assumed; the paper does not state it).")
]
KOpt = Annotated[str | None, typer.Option("--K", help="Feedback gain k1,k2; default pole placement.")]
WnOpt = Annotated[float, typer.Option("--pole-wn", help="Pole-placement natural frequency [rad/s].")]
ZetaOpt = Annotated[float, typer.Option("--pole-zeta", help="Pole-placement damping ratio.")]
SigmaAOpt = Annotated[
    float,
    typer.Option(
        "--sigma-a", help="True white-acceleration noise [m/s^2] (assumed; the paper does not state it)."
    ),
]
ROpt = Annotated[float | None, typer.Option("--R", help="1d: measurement-noise variance (default 1e-5).")]
RRangeOpt = Annotated[float | None, typer.Option("--R-range", help="2d: range-noise variance [m^2].")]
RBearingOpt = Annotated[float | None, typer.Option("--R-bearing", help="2d: bearing-noise variance [rad^2].")]
AnrPairOpt = Annotated[
    int | None,
    typer.Option(
        "--anr-pair",
        help="2d: Fig 7's (angle, range) ANR pair 1-4, in paper dB (10*ln) (9.2, 37.1) ... (101.3, 129.2); "
        "default 4.",
    ),
]
StartOpt = Annotated[
    str, typer.Option("--start", help="2d: initial position x,y [m] (the paper: 70,-20); zero velocity.")
]
SigAxesOpt = Annotated[
    SigAxes, typer.Option("--sig-axes", help="2d: axes whose reference carries the signature.")
]
AnrDbOpt = Annotated[
    float | None,
    typer.Option(
        "--anr-db",
        help="ANR (signature-amplitude-to-noise ratio a_sig^2/(2R)) in dB instead of --R; "
        "true decibels unless --db-convention paper-ln.",
    ),
]
DbConventionOpt = Annotated[
    DbConvention,
    typer.Option(
        "--db-convention",
        help="How --anr-db is read: log10, true decibels 10*log10(ANR); "
        "paper-ln, the paper's labels 10*ln(ANR) (48.3 is R = 1e-3 at a_sig 0.5).",
    ),
]
DurationOpt = Annotated[float, typer.Option("--duration", help="Record length [s].")]
CODES_HELP = (
    "The mode codes (mode i = code i): corrected or printed (Table I); gold:P1,P2 (the Gold family of a "
    "preferred pair, octal as encode gold takes it, in encode gold --all order), gold:P1,P2:K (its first K "
    "members) or gold:P1,P2:0,3,7 (members by --index; a-b ranges, u, v, k@a with start offset a); "
    "mseq:P[,P...] (m-sequences); gps:1-3,7 (GPS C/A PRNs); or a code table file (code,chip,value as "
    "encode writes it)."
)
CodesOpt = Annotated[str, typer.Option("--codes", help=CODES_HELP)]
NoSignatureOpt = Annotated[bool, typer.Option("--no-signature", help="Simulate H0 (no signature).")]
ZdotOpt = Annotated[
    str,
    typer.Option(
        "--zdot", help="Signature derivative in the velocity reference: analytic or finite-difference."
    ),
]

OPTIONS = {"m_rho": "--mrho", "f_c": "--fc", "wn": "--pole-wn", "zeta": "--pole-zeta", "anr_db": "--anr-db"}
DEFAULT_START = "70,-20"


@command(options=OPTIONS)
def simulate(
    example: ExampleOpt = Example.one_d,
    mode: ModeOpt = None,
    tau: TauOpt = None,
    tau_chips: TauChipsOpt = None,
    theta: ThetaOpt = "random",
    a_sig: ASigOpt = 0.5,
    a_r: AROpt = 10.0,
    f_r: FROpt = 0.01,
    fc: FcOpt = 1.0,
    f_d: FdOpt = None,
    feedback: FeedbackOpt = None,
    T: TOpt = 0.05,
    mrho: MrhoOpt = 20,
    K: KOpt = None,
    pole_wn: WnOpt = 4 * math.pi,
    pole_zeta: ZetaOpt = 0.7,
    sigma_a: SigmaAOpt = 0.01,
    R: ROpt = None,
    R_range: RRangeOpt = None,
    R_bearing: RBearingOpt = None,
    anr_pair: AnrPairOpt = None,
    start: StartOpt = DEFAULT_START,
    sig_axes: SigAxesOpt = SigAxes.both,
    anr_db: AnrDbOpt = None,
    db_convention: DbConventionOpt = DbConvention.log10,
    duration: DurationOpt = 80.0,
    codes: CodesOpt = "corrected",
    no_signature: NoSignatureOpt = False,
    zdot: ZdotOpt = "analytic",
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    *,
    output: Output,
) -> None:
    """Closed-loop vehicle whose position reference carries a mode signature: 1-D (eqs 53-55, Fig 2) or 2-D radar (eqs 59-60).

    Equations, figures and Table I are those of the mode-signature paper (47th IEEE CDC, Cancún, 2008). The random inputs are those of Monte Carlo trial 0 of
    `detect --montecarlo --seed SEED`.

    \b
    Example:
      motionsig simulate --mode 2 --tau-chips 5 --R 1e-3 --plot fig2.png | motionsig detect
      motionsig simulate --anr-db 21 --f-r 0.1 -o run.csv
      motionsig simulate --anr-db 48.3 --db-convention paper-ln | motionsig detect
      motionsig simulate --example 2d --anr-pair 3 --plot traj.png | motionsig detect
      motionsig simulate --f-d 0.02 | motionsig detect --fd-grid -0.04:0.04:0.01
      motionsig simulate --feedback estimate --R 1e-3
    """
    output.check()
    two_d = example is Example.two_d
    if two_d:
        _only_for(
            "--example 1d; use --R-range/--R-bearing or --anr-pair",
            {"--R": R, "--anr-db": anr_db, "--f-d": f_d, "--feedback": feedback},
        )
    else:
        planar = None if start == DEFAULT_START and sig_axes is SigAxes.both else start
        only_2d = {"--R-range": R_range, "--R-bearing": R_bearing, "--anr-pair": anr_pair}
        _only_for("--example 2d only", {**only_2d, "--start/--sig-axes": planar})
    from motionsig_cli.models.vehicle import Vehicle1D, measurement_variance, pole_placement_gain
    from motionsig_cli.models.vehicle2d import Vehicle2D, radar_noise
    from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record

    gains = pole_placement_gain(T, pole_wn, pole_zeta) if K is None else _numbers("--K", K, "gain")
    loop = dict(T=T, K=gains, a_sig=a_sig, a_r=a_r, f_r=f_r, sigma_a=sigma_a)
    pair = None
    if two_d:
        R_range, R_bearing, pair = radar_noise(anr_pair, R_range, R_bearing, a_sig)
        xy = _numbers("--start", start, "coordinate")
        vehicle = Vehicle2D(**loop, R_range=R_range, R_bearing=R_bearing, start=xy, sig_axes=sig_axes.value)
    else:
        extra = dict(f_d=0.0 if f_d is None else f_d, feedback="true" if feedback is None else feedback.value)
        vehicle = Vehicle1D(**loop, R=measurement_variance(R, anr_db, db_convention.value, a_sig), **extra)
    theta_value = None if theta.strip().lower() == "random" else common.checked("--theta", float, theta)
    cfg = RecordConfig(
        vehicle, mode=mode, tau=tau, tau_chips=tau_chips, theta=theta_value, f_c=fc, m_rho=mrho,
        duration=duration, codes=codes, signature=not no_signature, zdot=zdot, seed=seed, anr_pair=pair,
    )  # fmt: skip
    rec = simulate_record(cfg)
    if output.plot is not None:
        from motionsig_cli.plotting import radar_trajectory_figure, response_figure

        output.figure(
            radar_trajectory_figure(rec.t, rec.x, rec.r, rec.y)
            if rec.two_d
            else response_figure(rec.t, rec.x[:, 0], rec.r[:, 0], rec.combined_reference, rec.y)
        )
    output.emit(rec.table if anr_db is None else _with_convention(rec.table, anr_db, db_convention.value))
    output.note(rec.summary)


def _with_convention(table: Table, anr_db: float, convention: str) -> Table:
    """The record's table with the --anr-db value as given and its convention in the metadata, after the
    ANR in both conventions (anr_db_log10, anr_db_paper_ln)."""
    meta: dict[str, object] = {}
    for key, value in table.meta.items():
        meta[key] = value
        if key == "anr_db_paper_ln":
            meta.update(anr_db=anr_db, db_convention=convention)
    return dataclasses.replace(table, meta=meta)


def _only_for(where: str, given: dict[str, object]) -> None:
    """Refuse an option of the other example."""
    for option, value in given.items():
        if value is not None:
            raise typer.BadParameter(f"applies to {where}", param_hint=option)


def _numbers(option: str, text: str, what: str) -> tuple[float, ...]:
    """A comma-separated list of finite numbers (its length is checked by the configuration)."""
    return tuple(common.checked(option, common.float_list, text, what=what))
