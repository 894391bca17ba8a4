"""``motionsig simulate``: the closed-loop vehicle carrying a mode signature, after §IV.A (Fig 2) and §IV.B of
the mode-signature paper (47th IEEE CDC, Cancún, 2008).

The command parses the options, builds the vehicle and record configurations (which check every value)
and writes the table of :func:`motionsig_cli.modesig.vehicle_record.simulate_record`.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, SeedOpt, choices, command
from motionsig_cli.cli.option_groups import options
from motionsig_cli.cli.vehicle_options import vehicle_options

if TYPE_CHECKING:
    from motionsig_cli.tables import Table

Example = choices("Example", "Which example of the mode-signature paper.", one_d="1d", two_d="2d")
SigAxes = choices(
    "SigAxes", "Axes of the 2-D vehicle whose reference carries the signature.", "both", "x", "y"
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
SigAxesOpt = Annotated[
    SigAxes, typer.Option("--sig-axes", help="2d: axes whose reference carries the signature.")
]
DurationOpt = Annotated[float, typer.Option("--duration", help="Record length [s].")]
NoSignatureOpt = Annotated[bool, typer.Option("--no-signature", help="Simulate H0 (no signature).")]
ZdotOpt = Annotated[
    str,
    typer.Option(
        "--zdot", help="Signature derivative in the velocity reference: analytic or finite-difference."
    ),
]

OPTIONS = {"m_rho": "--mrho", "f_c": "--fc", "wn": "--pole-wn", "zeta": "--pole-zeta", "anr_db": "--anr-db"}
DEFAULT_START = "70,-20"
VehicleOptions = vehicle_options("simulate", "VehicleOptions")
"""The true vehicle's model options (:data:`~motionsig_cli.cli.vehicle_options.VEHICLE_OPTIONS`)."""
PAPER_VEHICLE = VehicleOptions()
"""The options' defaults (the signature's placeholder: :func:`options` splices in the fields)."""


@command(options=OPTIONS)
@options(model=VehicleOptions)
def simulate(
    example: ExampleOpt = Example.one_d,
    mode: ModeOpt = None,
    tau: TauOpt = None,
    tau_chips: TauChipsOpt = None,
    theta: ThetaOpt = "random",
    model: VehicleOptions = PAPER_VEHICLE,
    sig_axes: SigAxesOpt = SigAxes.both,
    duration: DurationOpt = 80.0,
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
    m = model
    two_d = example is Example.two_d
    if two_d:
        _only_for(
            "--example 1d; use --R-range/--R-bearing or --anr-pair",
            {"--R": m.R, "--anr-db": m.anr_db, "--f-d": m.f_d, "--feedback": m.feedback},
        )
    else:
        planar = None if m.start == DEFAULT_START and sig_axes is SigAxes.both else m.start
        only_2d = {"--R-range": m.R_range, "--R-bearing": m.R_bearing, "--anr-pair": m.anr_pair}
        _only_for("--example 2d only", {**only_2d, "--start/--sig-axes": planar})
    from motionsig_cli.models.vehicle import Vehicle1D, measurement_variance, pole_placement_gain
    from motionsig_cli.models.vehicle2d import Vehicle2D, radar_noise
    from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record

    gains = pole_placement_gain(m.T, m.pole_wn, m.pole_zeta) if m.K is None else _numbers("--K", m.K, "gain")
    loop = dict(T=m.T, K=gains, a_sig=m.a_sig, a_r=m.a_r, f_r=m.f_r, sigma_a=m.sigma_a)
    pair = None
    if two_d:
        R_range, R_bearing, pair = radar_noise(m.anr_pair, m.R_range, m.R_bearing, m.a_sig)
        xy = _numbers("--start", m.start, "coordinate")
        vehicle = Vehicle2D(**loop, R_range=R_range, R_bearing=R_bearing, start=xy, sig_axes=sig_axes.value)
    else:
        extra = dict(
            f_d=0.0 if m.f_d is None else m.f_d, feedback="true" if m.feedback is None else m.feedback.value
        )
        vehicle = Vehicle1D(
            **loop, R=measurement_variance(m.R, m.anr_db, m.db_convention.value, m.a_sig), **extra
        )
    theta_value = None if theta.strip().lower() == "random" else common.checked("--theta", float, theta)
    cfg = RecordConfig(
        vehicle, mode=mode, tau=tau, tau_chips=tau_chips, theta=theta_value, f_c=m.fc, m_rho=m.mrho,
        duration=duration, codes=m.codes, signature=not no_signature, zdot=zdot, seed=seed, anr_pair=pair,
    )  # fmt: skip
    rec = simulate_record(cfg)
    if output.plot is not None:
        from motionsig_cli.plotting import radar_trajectory_figure, response_figure

        output.figure(
            radar_trajectory_figure(rec.t, rec.x, rec.r, rec.y)
            if rec.two_d
            else response_figure(rec.t, rec.x[:, 0], rec.r[:, 0], rec.combined_reference, rec.y)
        )
    table = rec.table if m.anr_db is None else _with_convention(rec.table, m.anr_db, m.db_convention.value)
    output.emit(table)
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
