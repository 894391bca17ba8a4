"""``motionsig track-sat solve``: the transmitter's position and clock from a user's time-of-arrival record,
epoch by epoch (weighted least squares) and with the clock tracked across epochs (ATC-10, Schneider,
Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972, §4.5).

This module imports only typer and the command layer's helpers: the core
(:mod:`motionsig_cli.atc10.toa_solve`) is imported when the command runs.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import Output, choices, command
from motionsig_cli.cli.option_groups import options

OPTIONS = {
    "sigma_ns": "--sigma",
    "p_fa": "--p-fa",
    "fde": "--fde",
    "earth_rotation": "--earth-rotation",
    "sigma0_ns": "--sigma0",
    "receivers_columns": "--receivers-columns",
    "toa_origin": "--toa-origin",
    "full_covariance": "--full-covariance",
    "max_iter": "--max-iter",
    "reinit_after_outage": "--reinit-after-outage",
}
"""Configuration fields whose option is not ``--`` + the field's name."""

Clock = choices(
    "Clock", "Snapshot fixes only, or also the report's clock tracker across epochs.", "snapshot", "track"
)
SolveView = choices(
    "SolveView", "One row per epoch, or one per measurement (residuals).", "epochs", "residuals"
)
SolveGain = choices(
    "SolveGain",
    "Clock gain: the exact recursive γ_n, or the constant steady-state ψ(α).",
    "recursive",
    "steady",
)
ToaOrigin = choices("ToaOrigin", "What a TOA is measured from.", "time", "epoch")
Covariance = choices("Covariance", "Covariance of the fix.", "auto", "known", "epoch", "pooled")


def _units(text: str | None) -> tuple[str, str | None]:
    """``--units``: the output system (``si`` or ``report``) and the input units (``role=unit`` entries),
    e.g. ``report,toa=ns,x=km``."""
    if text is None:
        return "si", None
    system = "si"
    entries = []
    seen = 0
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        if "=" in part:
            entries.append(part)
        elif part.lower() in ("si", "report"):
            system, seen = part.lower(), seen + 1
        else:
            raise typer.BadParameter(
                f"{part!r} is neither si, report nor role=unit (e.g. --units report or --units toa=ns,x=km)",
                param_hint="--units",
            )
    if seen > 1:
        raise typer.BadParameter("names the output units twice", param_hint="--units")
    return system, ",".join(entries) or None


def _start(text: str | None) -> tuple[float, float, float] | None:
    if text is None:
        return None
    vals = common.checked("--start", common.float_list, text, what="latitude,longitude,altitude")
    if len(vals) != 3:
        raise typer.BadParameter(
            f"expected latitude,longitude,altitude (deg, deg, m), got {text!r}", param_hint="--start"
        )
    return (vals[0], vals[1], vals[2])


@dataclass(frozen=True)
class Solver:
    """How the record is read (``--toa-origin``, ``--sigma``) and solved: the fields of
    :class:`~motionsig_cli.atc10.toa_solve.SolveConfig` but its ``units``."""

    toa_origin: Annotated[
        ToaOrigin,
        typer.Option(
            "--toa-origin",
            help="time: TOAs share the time column's frame (absolute); epoch: each TOA is measured from its "
            "epoch's time.",
        ),
    ] = ToaOrigin.time
    sigma: Annotated[
        str | None,
        typer.Option(
            "--sigma",
            help="Error σ of every measurement, in the measurement's unit (s for TOAs and TDOAs, m for "
            "pseudoranges) or with a unit: 10ns, 3m; default the record's sigma column, else unknown.",
        ),
    ] = None
    covariance: Annotated[
        Covariance,
        typer.Option(
            "--covariance",
            help="auto: (H'WH)^-1 with the known σ, else scaled by each epoch's variance factor; known; epoch or "
            "pooled: scaled by each epoch's or the pooled a-posteriori variance factor.",
        ),
    ] = Covariance.auto
    clock: Annotated[
        Clock,
        typer.Option(
            "--clock", help="snapshot (a fix per epoch) or track (also the report's clock tracker)."
        ),
    ] = Clock.snapshot
    sigma0: Annotated[
        float | None,
        typer.Option(
            "--sigma0",
            help="Clock model scale σ0 [ns] per epoch (σ1 = σ2 = σ0, ρ = 1; default 50, as simulate).",
        ),
    ] = None
    gain: Annotated[
        SolveGain, typer.Option("--gain", help="recursive γ_n (exact) or steady ψ(α) from the first epoch.")
    ] = SolveGain.recursive
    reinit_after_outage: Annotated[
        bool,
        typer.Option(
            "--reinit-after-outage",
            help="Restart the tracker by least squares after epochs with fewer than 4 receivers (the report).",
        ),
    ] = False
    relinearise: Annotated[
        int, typer.Option("--relinearise", help="Extra linearisations per epoch of the tracker (0-10).")
    ] = 2
    start: Annotated[
        str | None,
        typer.Option(
            "--start",
            help="Gauss-Newton starting point latitude,longitude,altitude (deg, deg, m); default the closed-form "
            "solution (Bancroft), above the receivers' plane for a ground network. For ground receivers it also "
            "says on which side of their plane the transmitter is (the mirror image fits about as well).",
        ),
    ] = None
    max_iter: Annotated[int, typer.Option("--max-iter", help="Gauss-Newton steps per epoch (1-1000).")] = 20
    view: Annotated[
        SolveView,
        typer.Option("--view", help="epochs (one row per epoch) or residuals (one per measurement)."),
    ] = SolveView.epochs
    full_covariance: Annotated[
        bool,
        typer.Option(
            "--full-covariance", help="Add the covariance of x, y, z and the clock offset as columns."
        ),
    ] = False
    fde: Annotated[
        bool,
        typer.Option(
            "--fde/--no-fde",
            help="Fault detection and exclusion: chi-square test of each epoch's residuals, the most likely "
            "faulty receiver excluded and the epoch solved again while 5 or more remain (needs σ).",
        ),
    ] = True
    p_fa: Annotated[
        float, typer.Option("--p-fa", help="False-alarm probability of the fault test per epoch, (0, 0.5].")
    ] = 1e-3
    earth_rotation: Annotated[
        bool,
        typer.Option(
            "--earth-rotation",
            help="Rotate the anchors by the Earth's rotation during the signal's flight (Sagnac): for "
            "satellite positions given at the transmission time.",
        ),
    ] = False

    def config(self, units: str) -> Any:
        """The solver's configuration (which checks every value), in output units ``units``."""
        from motionsig_cli.atc10 import toa_solve as ts

        return ts.SolveConfig(
            clock=self.clock.value, sigma=self.sigma, sigma0_ns=self.sigma0, gain=self.gain.value,
            reinit_after_outage=self.reinit_after_outage, relinearise=self.relinearise, units=units,
            toa_origin=self.toa_origin.value, covariance=self.covariance.value, start=_start(self.start),
            max_iter=self.max_iter, view=self.view.value, full_covariance=self.full_covariance, fde=self.fde,
            p_fa=self.p_fa, earth_rotation=self.earth_rotation,
        )  # fmt: skip


@command(plot=False, options=OPTIONS)
@options(solver=Solver)
def solve(
    measurements: Annotated[
        str,
        typer.Argument(
            help="TOA record (CSV or JSON; '-' for stdin): epoch and/or time, receiver, toa [s], tdoa [s] or "
            "pseudorange [m], optional sigma, and the receivers' positions unless --receivers gives them.",
            show_default=False,
        ),
    ],
    receivers: Annotated[
        Path | None,
        typer.Option(
            "--receivers",
            help="Receivers file: receiver, and x,y,z [m] (ECEF) or latitude,longitude [deg], altitude [m] "
            "(WGS-84); optionally epoch or time for positions that change per epoch.",
        ),
    ] = None,
    columns: Annotated[
        str | None,
        typer.Option(
            "--columns", help="Which column of the record is which role, e.g. toa=arrival_s,receiver=site."
        ),
    ] = None,
    receivers_columns: Annotated[
        str | None, typer.Option("--receivers-columns", help="The same for the --receivers file.")
    ] = None,
    units: Annotated[
        str | None,
        typer.Option(
            "--units",
            help="Output units: si (m, s; default) or report (ft, ns, as the report's tables); and/or input "
            "units role=unit, e.g. --units report,toa=ns,x=km (header 'toa [ns]' works too).",
        ),
    ] = None,
    solver: Solver = Solver(),
    *,
    output: Output,
) -> None:
    """Position and clock of a transmitter from times of arrival at several receivers (ATC-10 §4), epoch by
    epoch by weighted least squares, and with the report's clock tracker across epochs (§4.5).

    Output per epoch: ECEF x, y, z, latitude, longitude, altitude (WGS-84), the clock offset (emission
    time minus the epoch's time), their standard deviations, GDOP/PDOP/HDOP/VDOP/TDOP, the number of
    receivers, the RMS residual, a status (why an epoch has no fix), the receivers excluded as faulty and
    the fault test's statistic and threshold; with --clock track the tracked clock and position beside them
    (3 receivers: the position from the clock prediction, the report's outage case). Ionosphere,
    troposphere, satellite clocks and ephemerides are the user's corrections.

    \b
    Example:
      motionsig track-sat solve toa.csv --receivers stations.csv              # one fix per epoch
      motionsig track-sat solve toa.csv --receivers stations.csv --clock track --sigma0 20 --sigma 10
      motionsig track-sat solve toa.csv --receivers stations.csv --view residuals --units report
      motionsig track-sat solve gps.csv --earth-rotation --sigma 5m         # GNSS pseudoranges
    """
    from motionsig_cli.atc10 import toa_solve as ts

    output.check()
    system, input_units = _units(units)
    output.refuse_input(measurements, "the measurement record")
    cfg = solver.config(system)
    meas = ts.read_measurements(
        measurements,
        columns=columns,
        units=input_units,
        receivers=receivers,
        receivers_columns=receivers_columns,
        toa_origin=cfg.toa_origin,
        sigma=cfg.sigma,
    )
    report = ts.solve_report(meas, cfg)
    output.emit(report.table)
    for w in report.warnings:
        output.note(f"track-sat solve: warning: {w}")
    output.note(report.summary)
