"""The model options of the mode-signature vehicle, declared once for ``simulate`` and ``detect``.

``simulate`` sets the true vehicle with them (eqs 53–55, 59–60: each option has the paper's value, or our
assumption, as its default); ``detect`` sets the model its filters assume (each option defaults to None:
the record's metadata, else ``simulate``'s default; for ``--montecarlo``/``--calibrate`` the simulated
vehicle's and the filters'). The flag, the value type and the quantity of each option are written once, in
:data:`VEHICLE_OPTIONS`; each command adds what its default is. :func:`vehicle_options` builds the option
group (:mod:`motionsig_cli.cli.option_groups`) of one command.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import typer

from motionsig_cli.cli.common import choices

__all__ = ["VEHICLE_OPTIONS", "DbConvention", "Feedback", "VehicleOption", "vehicle_options"]

Feedback = choices("Feedback", "What the vehicle's controller feeds back (eq 5).", "true", "estimate")
DbConvention = choices(
    "DbConvention",
    "How an ANR (signature-amplitude-to-noise ratio) given in dB is read.",
    "log10",
    "paper-ln",
)

CODES_HELP = (
    "The mode codes (mode i = code i): corrected or printed (Table I); gold:P1,P2 (the Gold family of a "
    "preferred pair, octal as encode gold takes it, in encode gold --all order), gold:P1,P2:K (its first K "
    "members) or gold:P1,P2:0,3,7 (members by --index; a-b ranges, u, v, k@a with start offset a); "
    "mseq:P[,P...] (m-sequences); gps:1-3,7 (GPS C/A PRNs); or a code table file (code,chip,value as "
    "encode writes it)."
)
_REC = "a record: default the record's metadata, else"
_MC = "--montecarlo/--calibrate"
_TRUTH = (
    f"The true vehicle's ({_MC}: the simulated one's; a record: for the null records of --pfa, and for "
    "--Ar known, which the filters assume it for)"
)
_F_D = (
    "Carrier offset f_d [Hz] of the received signature (eq 3: cos(2 pi (f_c + f_d) t + theta)); default 0, "
    "as in the paper. The detector does not assume it: search it with --fc-grid or --fd-grid."
)
_FEEDBACK = (
    "1d: the controller on the true state (true, eq 44; the default) or on the vehicle's own estimate "
    "(estimate, eq 5: a Kalman filter of its own position sensor, noise R, assumed)."
)


@dataclass(frozen=True)
class VehicleOption:
    """One model option: its parameter name, flag and value type, and each command's default and help.

    Attributes:
        name: The command's parameter (and the option group's field).
        flag: The option, e.g. ``--T``.
        kind: The value's type (``float``, ``int``, ``str`` or a choices enum).
        simulate: ``simulate``'s default (the paper's value or our assumption; None: resolved in the command).
        simulate_help: ``simulate``'s help: the true vehicle.
        detect_help: ``detect``'s help: the model the filters assume, and where its value comes from.
        detect: ``detect``'s default (None: the record's metadata, else ``simulate``'s default).
    """

    name: str
    flag: str
    kind: Any
    simulate: Any
    simulate_help: str
    detect_help: str
    detect: Any = None


VEHICLE_OPTIONS: tuple[VehicleOption, ...] = (
    VehicleOption("a_sig", "--a-sig", float, 0.5, "Signature amplitude a_sig (the paper: 0.5).",
                  "Signature amplitude (a record: for --anr-db, --anr-pair; default the record's metadata, else "
                  f"0.5; {_MC}: the simulated signature's, 0.5)."),
    VehicleOption("a_r", "--a-r", float, 10.0, "Nominal reference amplitude (the paper: 10).",
                  f"{_TRUTH} nominal reference amplitude; {_REC} 10; default 10."),
    VehicleOption("f_r", "--f-r", float, 0.01, "Nominal reference frequency [Hz] (the paper: 0.01, 0.1, 1).",
                  "A record: the true vehicle's nominal reference frequency [Hz] (for the null records of "
                  f"--pfa, and for --Ar known, which the filters assume it for); default the record's "
                  f"metadata, else 0.01. {_MC}: --fr-list."),
    VehicleOption("fc", "--fc", float, 1.0, "Carrier frequency f_c [Hz].",
                  f"The signature's carrier frequency f_c [Hz], the default carrier grid; {_REC} 1; {_MC}: 1."),
    VehicleOption("f_d", "--f-d", float, None, _F_D, _F_D),
    VehicleOption("feedback", "--feedback", Feedback, None, _FEEDBACK, _FEEDBACK),
    VehicleOption("T", "--T", float, 0.05, "Sample interval [s] (assumed; the paper does not state it).",
                  f"Sample interval [s]. A record: default the record's metadata, else estimated from the time "
                  f"column; {_MC}: the simulated vehicle's and the filters', default 0.05 (assumed). The "
                  "records' length is horizon / T samples."),
    VehicleOption("mrho", "--mrho", int, 20, "Samples per chip (assumed; the paper does not state it).",
                  f"Samples per chip ({_REC} 20; {_MC}: 20; assumed)."),
    VehicleOption("K", "--K", str, None, "Feedback gain k1,k2; default pole placement.",
                  f"Feedback gain k1,k2 the filters assume ({_MC}: the simulated vehicle's too); {_REC} pole "
                  "placement; default pole placement at T."),
    VehicleOption("pole_wn", "--pole-wn", float, 4 * math.pi, "Pole-placement natural frequency [rad/s].",
                  "Pole placement for K at T, natural frequency [rad/s] (default 4 pi)."),
    VehicleOption("pole_zeta", "--pole-zeta", float, 0.7, "Pole-placement damping ratio.",
                  "Pole placement for K at T, damping ratio (default 0.7)."),
    VehicleOption("sigma_a", "--sigma-a", float, 0.01,
                  "True white-acceleration noise [m/s^2] (assumed; the paper does not state it).",
                  f"{_TRUTH} white-acceleration noise [m/s^2]; {_REC} 0.01; default 0.01 (assumed)."),
    VehicleOption("R", "--R", float, None, "1d: measurement-noise variance (default 1e-5).",
                  f"1d record: measurement-noise variance [m^2] the filters assume; {_REC} 1e-5."),
    VehicleOption("R_range", "--R-range", float, None, "2d: range-noise variance [m^2].",
                  f"2d record: range-noise variance [m^2]; {_REC} Fig 7 pair 4."),
    VehicleOption("R_bearing", "--R-bearing", float, None, "2d: bearing-noise variance [rad^2].",
                  f"2d record: bearing-noise variance [rad^2]; {_REC} Fig 7 pair 4."),
    VehicleOption("anr_pair", "--anr-pair", int, None,
                  "2d: Fig 7's (angle, range) ANR pair 1-4, in paper dB (10*ln) (9.2, 37.1) ... (101.3, "
                  "129.2); default 4.",
                  "2d record: both noise variances from Fig 7's (angle, range) ANR pair 1-4."),
    VehicleOption("start", "--start", str, "70,-20",
                  "2d: initial position x,y [m] (the paper: 70,-20); zero velocity.",
                  f"2d record: the filters' initial position x,y [m]; {_REC} the first measured position."),
    VehicleOption("anr_db", "--anr-db", float, None,
                  "ANR (signature-amplitude-to-noise ratio a_sig^2/(2R)) in dB instead of --R; true decibels "
                  "unless --db-convention paper-ln.",
                  "1d record: the ANR a_sig^2/(2R) in dB instead of --R (true decibels unless --db-convention "
                  "paper-ln)."),
    VehicleOption("db_convention", "--db-convention", DbConvention, DbConvention.log10,
                  "How --anr-db is read: log10, true decibels 10*log10(ANR); paper-ln, the paper's labels "
                  "10*ln(ANR) (48.3 is R = 1e-3 at a_sig 0.5).",
                  "How --anr-db is read: log10 (true decibels) or paper-ln (10*ln).", DbConvention.log10),
    VehicleOption("codes", "--codes", str, "corrected", CODES_HELP,
                  f"Record: {CODES_HELP[0].lower()}{CODES_HELP[1:]} Default the record's metadata, else "
                  "corrected."),
)  # fmt: skip
"""The model options, in the order of ``--help``."""


def vehicle_options(
    command: Literal["simulate", "detect"],
    name: str,
    *,
    before: tuple[tuple[str, Any, Any], ...] = (),
    namespace: dict[str, Any] | None = None,
) -> type:
    """The option group of ``command``'s model options: a frozen dataclass called ``name`` with the fields
    ``before`` (name, ``Annotated`` declaration, default) and then one field per :data:`VEHICLE_OPTIONS`
    member, declared with ``command``'s default and help. ``namespace`` adds methods."""
    fields: list[tuple[str, Any, Any]] = [(n, t, dataclasses.field(default=d)) for n, t, d in before]
    for opt in VEHICLE_OPTIONS:
        sim = command == "simulate"
        default = opt.simulate if sim else opt.detect
        kind = opt.kind if default is not None else opt.kind | None
        decl = typer.Option(opt.flag, help=opt.simulate_help if sim else opt.detect_help)
        fields.append((opt.name, Annotated[kind, decl], dataclasses.field(default=default)))
    return dataclasses.make_dataclass(name, fields, frozen=True, namespace=namespace)
