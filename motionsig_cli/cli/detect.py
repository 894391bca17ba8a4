"""``motionsig detect``: the LMP mode detector of eq (52) of the mode-signature paper (47th IEEE CDC, Cancún, 2008) on a record (a simulate record or a user's own export), the Monte Carlo
study of Figs 4–6 (``--montecarlo``), its threshold calibration (``--calibrate``) and, for 2-D radar records,
Fig 7 (:mod:`motionsig_cli.cli.detect_radar`).

The command parses the options, reads the record
(:func:`motionsig_cli.modesig.record_reading.read_vehicle_record`: its columns, units, missing samples,
and the model the filters assume: each quantity from the option of simulate's name, else the record's
metadata, else simulate's default), builds the detector's configuration and one run of
:mod:`motionsig_cli.modesig.lmp1d` (a record's :class:`~motionsig_cli.modesig.lmp1d.RecordDetection`,
or a Monte Carlo job), and writes its table and figure. Every range is checked by those configurations.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import (
    DEFAULT_SEED_VALUE,
    Output,
    Parallel,
    SeedOpt,
    choices,
    command,
    progress_bar,  # by name: a test replaces detect.progress_bar
)
from motionsig_cli.cli.option_groups import options
from motionsig_cli.cli.vehicle_options import vehicle_options

if TYPE_CHECKING:
    from motionsig_cli.engine import Engine
    from motionsig_cli.filters.unscented import SigmaPointParams
    from motionsig_cli.modesig.record_reading import VehicleRecord

R_LIST_DEFAULT = "1e-1,1e-2,1e-3,1e-5"
ANR_PAIRS_DEFAULT = "1,2,3,4"
# configuration fields whose option is not "--" + the field's name with "-" for "_"
OPTIONS = {
    "Q_a": "--Qa", "A_r": "--Ar", "horizons_s": "--horizons", "m_rho": "--mrho", "f_c": "--fc",
    "wn": "--pole-wn", "zeta": "--pole-zeta", "anr_db": "--anr-db",
}  # fmt: skip
RECORD_OPTIONS = {
    "--columns": "columns", "--units": "units", "--T": "T", "--mrho": "m_rho", "--K": "K", "--pole-wn": "wn",
    "--pole-zeta": "zeta", "--R": "R", "--anr-db": "anr_db", "--fc": "f_c", "--a-sig": "a_sig",
    "--codes": "codes", "--R-range": "R_range", "--R-bearing": "R_bearing", "--anr-pair": "anr_pair",
    "--start": "start", "--a-r": "a_r", "--f-r": "f_r", "--sigma-a": "sigma_a", "--f-d": "f_d",
    "--feedback": "feedback",
}  # fmt: skip
"""The options that describe a record's model → their field."""
MODEL_OPTIONS = (
    "--T", "--mrho", "--K", "--pole-wn", "--pole-zeta", "--fc", "--a-sig", "--a-r", "--sigma-a", "--f-d",
    "--feedback",
)  # fmt: skip
"""Those of :data:`RECORD_OPTIONS` that the 1d --montecarlo and --calibrate take too (the vehicle they
simulate and the filters assume); the others are refused there."""
RECORD_ONLY = ("--f-d",)
"""Model options that describe the simulated truth only: refused on a record."""


TauGrid = choices("TauGrid", "Code-phase search grid.", "chips", "samples")
Weights = choices("Weights", "cos/sin gain weighting.", "paper", "exact")
Center = choices("Center", "H0 centring of the statistic.", "none", "h0-noise", "standardised")
Zdot = choices("Zdot", "Replica derivative in the a-column of eq 44.", "analytic", "finite-difference")
FilterKind = choices("FilterKind", "Filter bank.", "auto", "kf", "ukf")
Method = choices("Method", "How the statistic is computed.", "bank", "fft", "linearised")
ExampleKind = choices("ExampleKind", "Example of the paper for --montecarlo.", one_d="1d", two_d="2d")
Ar = choices("Ar", "The nominal reference in the filters.", "cv", "identity", "known")
QModel = choices("QModel", "How the filters' Q matrices are read.", "per-step", "continuous")
Detector = choices("Detector", "The detector --calibrate calibrates.", "lmp", "estimate-correlate")
Preset = choices("Preset", "A reading of what the mode-signature paper leaves open.", "none", "paper")


SourceArg = Annotated[
    str,
    typer.Argument(
        help="The record: CSV (optional '# key: value' metadata) or the JSON the commands write, - for stdin "
        "(ignored with --montecarlo)."
    ),
]
ColumnsOpt = Annotated[
    str | None,
    typer.Option(
        "--columns",
        help="Record: the columns of its roles, role=name,... : time (also t, timestamp; seconds or ISO "
        "8601) and y (also position, z) for 1d; time with range and bearing, or x and y (radar at the origin), "
        "for 2d.",
    ),
]
UnitsOpt = Annotated[
    str | None,
    typer.Option(
        "--units",
        help="Record: units of its columns, role=unit,... (e.g. y=km, bearing=deg, time=ms); default the "
        "header's [unit], the metadata's, else m, rad, s.",
    ),
]
CrOpt = Annotated[
    float | None,
    typer.Option(
        "--c-r",
        help="Filter measurement covariance R_KF = c_r R (the paper's Fig 3: 1 or 100; Figs 4-6: not stated). "
        "Default 100.",
    ),
]
PresetOpt = Annotated[
    Preset,
    typer.Option(
        "--preset",
        help="1d: paper = our reading of what the paper prints garbled or leaves open for Figs 3-6, not values "
        "it states: the reading of data/lmp_search.csv with the most of its claims' checks holding (eq 56's "
        "positive exponents as lost minus signs, --Q0 1e-3,1e-2,1e-1,1e-1; eq 57's last entry read "
        "literally, --Qa 100; c_r = 100). --c-r, --Q0 and --Qa given explicitly win.",
    ),
]
Q0Opt = Annotated[
    str | None,
    typer.Option(
        "--Q0",
        help="H0 Q diagonal: 1d [x, xdot, r, rdot] (eq 56; per step, or densities with --q-model "
        "continuous; --Ar known uses the first two); 2d 8 values per step (eq 61).",
    ),
]
QaOpt = Annotated[
    float | None,
    typer.Option("--Qa", help="1d: Q of the amplitude state (eq 57: 10^0; --method fft: 0, which it needs)."),
]
QModelOpt = Annotated[
    QModel,
    typer.Option(
        "--q-model",
        help="1d: per-step (--Q0, --Qa are covariances of one step, as printed) or continuous (densities "
        "per second, discretised over T by Van Loan's method for the filters' F; --Qa becomes Qa*T).",
    ),
]
MethodOpt = Annotated[
    Method,
    typer.Option(
        "--method",
        help="1d: bank (2C+1 Kalman filters, eq 52) or fft (one steady-state filter and FFT "
        "cross-correlations: exact identity for Qa = 0, and a steady-state approximation whose relative "
        "error falls like 1/horizon, ~5 % of Lambda at 10 s and 0.7 % at 80 s with the defaults). 2d: bank "
        "(2C+1 sigma-point filters) or linearised (one H0 and one base filter per record and a projection of "
        "the filtered replicas: exact for a linear measurement with constant amplitudes, an approximation on "
        "the radar; the default of 2d --calibrate).",
    ),
]
Q1Opt = Annotated[str | None, typer.Option("--Q1", help="2d: per-step H1 Q, 10 values (eq 62).")]
FilterOpt = Annotated[
    FilterKind,
    typer.Option(
        "--filter",
        help="auto: kf (Kalman filters) for 1d records, ukf (unscented Kalman filters) for 2d; ukf on 1d "
        "runs the sigma-point bank.",
    ),
]
AlphaOpt = Annotated[float, typer.Option("--alpha", help="Unscented transform: spread alpha (assumed: 1).")]
BetaOpt = Annotated[float, typer.Option("--beta", help="Unscented transform: beta (2: Gaussian).")]
KappaOpt = Annotated[float, typer.Option("--kappa", help="Unscented transform: kappa (assumed: 0).")]
ExampleOpt = Annotated[
    ExampleKind | None,
    typer.Option(
        "--example",
        help="--montecarlo: 1d (Figs 4-6) or 2d (Fig 7). A record says which it is (its metadata or "
        "columns); this forces it: 1d reads time and y, 2d range and bearing, or x and y.",
    ),
]
AnrPairsOpt = Annotated[
    str, typer.Option("--anr-pairs", help="2d --montecarlo: Fig 7 (angle, range) ANR pairs 1-4.")
]
P0Opt = Annotated[
    float,
    typer.Option("--P0", help="Prior covariance P0 = P0 * I (assumed: 1; the paper does not state it)."),
]
ArOpt = Annotated[
    Ar,
    typer.Option(
        "--Ar",
        help="1d: the nominal reference in the filters: a random walk, cv or identity (assumed: cv; the paper "
        "does not state it), or known: the vehicle's own commanded reference (a_r, f_r) as a known input "
        "(a cooperative setting; a record must state a_r and f_r, or give --a-r, --f-r).",
    ),
]
TauGridOpt = Annotated[
    TauGrid,
    typer.Option("--tau-grid", help="chips (n_rho phases: 31 for Table I) or samples (all n_rho*m_rho)."),
]
FcGridOpt = Annotated[
    str | None, typer.Option("--fc-grid", help="Candidate carrier frequencies [Hz]; default the known f_c.")
]
FdGridOpt = Annotated[
    str | None,
    typer.Option(
        "--fd-grid",
        help="Candidate carrier offsets f_d [Hz] around f_c (eq 3), a list or lo:hi:n (n points), instead of "
        "--fc-grid; the output's fc_hat is the estimated carrier f_c + f_d.",
    ),
]
LogdetOpt = Annotated[
    bool,
    typer.Option("--include-logdet", help="Use the full -log-likelihood (add 1/2 sum log det 2 pi S)."),
]
WeightsOpt = Annotated[
    Weights, typer.Option("--weights", help="paper: eq 42 (weights dropped); exact: eqs 38/40.")
]
ZdotOpt = Annotated[
    Zdot,
    typer.Option("--zdot", help="Replica derivative: analytic (chip edges ignored) or finite-difference."),
]
CenterOpt = Annotated[
    Center,
    typer.Option(
        "--center",
        help="none: the paper's eq 52; h0-noise (ours): subtract E[Lambda] under white noise (reduces the H0 "
        "bias); standardised (ours, 2d --method linearised): the z-score of each candidate's statistic.",
    ),
]
HorizonsOpt = Annotated[
    str | None, typer.Option("--horizons", help="Horizons [s], e.g. 10,20,40; default every 10 s.")
]
ThresholdOpt = Annotated[
    float | None,
    typer.Option(
        "--threshold",
        help="Record: declare 'signature present' when max Lambda >= this (a fixed threshold; --pfa "
        "calibrates one).",
    ),
]
CandidatesOpt = Annotated[
    bool, typer.Option("--candidates", help="Output the full candidate table instead of the argmax.")
]
MonteCarloOpt = Annotated[
    bool, typer.Option("--montecarlo", help="Monte Carlo % correct vs horizon and ANR (Figs 4-6).")
]
TrialsOpt = Annotated[int, typer.Option("--trials", help="Monte Carlo trials per (f_r, R) cell.")]
FrListOpt = Annotated[
    str | None,
    typer.Option("--fr-list", help="Monte Carlo reference frequencies [Hz] (1d: 0.01,0.1,1.0; 2d: 0.01)."),
]
RListOpt = Annotated[str, typer.Option("--R-list", help="Monte Carlo measurement variances.")]
NoSignatureOpt = Annotated[
    bool, typer.Option("--no-signature", help="Monte Carlo under H0 (argmax should be uniform).")
]
CalibrateOpt = Annotated[
    bool,
    typer.Option(
        "--calibrate",
        help="1d: the null distribution of max Lambda (no signature), the threshold for --pfa and "
        "P_D at it vs horizon and ANR; --plot draws ROC curves. Use --method fft: the bank costs "
        "~0.05 s per trial, and the default 20/pfa null trials per cell add up. 2d (--example 2d): the same "
        "for Fig 7's ANR pairs, with the linearised path unless --method bank is given (the bank costs ~30 s "
        "per 50 trials and pair).",
    ),
]
PfaOpt = Annotated[
    float | None,
    typer.Option(
        "--pfa",
        help="Target false-alarm probability: on a record, test for a signature at a threshold calibrated "
        "on null records simulated from the record's model (same length and missing samples, no "
        "signature); with --calibrate, the Monte Carlo's (default 0.01).",
    ),
]
DetectorOpt = Annotated[
    Detector,
    typer.Option(
        "--detector",
        help="--calibrate (1d): lmp (eq 52) or estimate-correlate (the baseline the paper's LMP replaces: a "
        "Kalman estimate of the command correlated with every replica), on the same records.",
    ),
]
NullTrialsOpt = Annotated[
    int | None,
    typer.Option("--null-trials", help="--pfa on a record, or --calibrate: null trials (default 20 / pfa)."),
]


def _by_field(self: Any) -> dict[str, Any]:
    """The options by the field of :data:`RECORD_OPTIONS` they set."""
    values = dataclasses.asdict(self)
    values["feedback"] = None if self.feedback is None else self.feedback.value
    return {key: values[_PARAMETER.get(key, key)] for key in RECORD_OPTIONS.values()}


RecordModel = vehicle_options(
    "detect", "RecordModel", before=(("columns", ColumnsOpt, None), ("units", UnitsOpt, None)),
    namespace={"by_field": _by_field},
)  # fmt: skip
"""The record's columns and the model the filters assume (None: the record's metadata, else simulate's
default; :data:`~motionsig_cli.cli.vehicle_options.VEHICLE_OPTIONS`); the 1d --montecarlo and --calibrate
take the model options of :data:`MODEL_OPTIONS` too."""
NO_MODEL_OPTIONS = RecordModel()
"""The group with no option given (the signature's placeholder: :func:`options` splices in the fields)."""


_PARAMETER = {"m_rho": "mrho", "wn": "pole_wn", "zeta": "pole_zeta", "f_c": "fc"}
"""Fields of :data:`RECORD_OPTIONS` whose parameter has another name."""


@command(parallel=True, options=OPTIONS)
@options(model=RecordModel)
def detect(
    source: SourceArg = "-",
    c_r: CrOpt = None,
    Q0: Q0Opt = None,
    preset: PresetOpt = Preset.none,
    Qa: QaOpt = None,
    q_model: QModelOpt = QModel.per_step,
    method: MethodOpt = Method.bank,
    Q1: Q1Opt = None,
    filter_: FilterOpt = FilterKind.auto,
    alpha: AlphaOpt = 1.0,
    beta: BetaOpt = 2.0,
    kappa: KappaOpt = 0.0,
    example: ExampleOpt = None,
    anr_pairs: AnrPairsOpt = ANR_PAIRS_DEFAULT,
    P0: P0Opt = 1.0,
    Ar_: ArOpt = Ar.cv,
    tau_grid: TauGridOpt = TauGrid.chips,
    fc_grid: FcGridOpt = None,
    fd_grid: FdGridOpt = None,
    include_logdet: LogdetOpt = False,
    weights: WeightsOpt = Weights.paper,
    zdot: ZdotOpt = Zdot.analytic,
    center: CenterOpt = Center.none,
    horizons: HorizonsOpt = None,
    threshold: ThresholdOpt = None,
    candidates: CandidatesOpt = False,
    montecarlo: MonteCarloOpt = False,
    trials: TrialsOpt = 50,
    fr_list: FrListOpt = None,
    R_list: RListOpt = R_LIST_DEFAULT,
    no_signature: NoSignatureOpt = False,
    calibrate_: CalibrateOpt = False,
    pfa: PfaOpt = None,
    null_trials: NullTrialsOpt = None,
    detector: DetectorOpt = Detector.lmp,
    model: RecordModel = NO_MODEL_OPTIONS,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    *,
    output: Output,
    parallel: Parallel,
) -> None:
    """LMP mode detector: Lambda(i,tau,f_c) = 2 J_H0 - J_H1,cos - J_H1,sin from a filter bank (eq 52).

    1-D records run a Kalman bank; 2-D radar records (range, bearing or x, y) a sigma-point bank. A record
    may be a simulate record or your own export: what it lacks of the model comes from simulate's options
    (--T, --mrho, --K, --R, --fc, --codes ...), else simulate's defaults (the output's metadata says
    which); missing samples (empty or NaN cells, absent times) are predict-only steps. The argmax is
    reported whether or not a signature is present: --pfa P tests for one. --montecarlo gives Figs 4-6
    (1d) or Fig 7 (--example 2d).

    \b
    Example:
      motionsig simulate --mode 2 --tau-chips 5 | motionsig detect
      motionsig simulate --R 1e-3 | motionsig detect --candidates --horizons 62 --plot fig3.png
      motionsig detect export.csv --columns time=timestamp,y=pos --units y=km --R 1e-3 --pfa 0.01
      motionsig simulate --codes gold:45,75:5 | motionsig detect
      motionsig detect --montecarlo --trials 50 --fr-list 0.01 --plot fig4.png -o fig4.csv
      motionsig detect --montecarlo --method fft --fr-list 1.0 --Ar known --T 0.1 --mrho 10
      motionsig simulate --example 2d | motionsig detect
      motionsig detect --montecarlo --example 2d --trials 50 --plot fig7.png
    """
    from motionsig_cli.filters.unscented import SigmaPointParams

    output.check()
    engine, sigma = parallel.engine(), SigmaPointParams(alpha, beta, kappa)
    rec = _record_or_study(source, example, model.by_field(), model.db_convention.value, montecarlo or calibrate_,
                           calibrate_, threshold, pfa, candidates, null_trials)  # fmt: skip
    two_d = example is ExampleKind.two_d or (rec is not None and rec.y.ndim == 2)
    _refuse_for_baseline(detector, calibrate_, two_d, locals())
    _refuse_other_example(two_d, {"--Qa": Qa is not None, "--method": method is Method.fft,
                                  "--Ar": Ar_ is not Ar.cv, "--weights": weights is not Weights.paper,
                                  "--R-list": R_list != R_LIST_DEFAULT, "--anr-pairs": anr_pairs != ANR_PAIRS_DEFAULT,
                                  "--Q1": Q1 is not None, "--q-model": q_model is not QModel.per_step})  # fmt: skip
    _check_method(method, filter_, two_d)
    c_r, Q0, Qa = _preset(preset, two_d, c_r, Q0, Qa)
    hs = _floats("--horizons", horizons, "horizon")
    grid = dict(c_r=c_r, P0=P0, tau_grid=tau_grid.value, include_logdet=include_logdet, zdot=zdot.value)
    f_known = rec.f_c if rec is not None else 1.0 if model.fc is None else model.fc
    carriers = _carriers(fc_grid, fd_grid, f_known, model.fc is not None and rec is None)
    grid |= _given(Q0=_floats("--Q0", Q0, "variance"), fc_grid=carriers)
    calibration = None if pfa is None or rec is None else (pfa, null_trials, seed)
    if two_d:
        from motionsig_cli.cli.detect_radar import detect_radar

        radar = dict(grid, sigma=sigma, **_given(Q1=_floats("--Q1", Q1, "variance")))
        return detect_radar(output, engine, rec, montecarlo, filter_, radar, hs, threshold, candidates,
                            _floats("--fr-list", fr_list or "0.01", "frequency"), anr_pairs, trials, seed,
                            not no_signature, calibration, method=method.value, center=center.value,
                            calibrate=calibrate_, pfa=pfa, null_trials=null_trials)  # fmt: skip
    lmp = dict(grid, Q_a=Qa if Qa is not None else 0.0 if method is Method.fft else 1.0, A_r=Ar_.value,
               weights=weights.value, center=center.value, q_model=q_model.value)  # fmt: skip
    mc = (_floats("--R-list", R_list, "variance"), hs, trials, seed, method.value)
    if montecarlo or calibrate_:
        return _study(output, engine, lmp, mc, _mc_model(model.by_field(), f_known), filter_, fr_list, calibrate_, pfa,
                      null_trials, not no_signature, detector)  # fmt: skip
    kind = "ukf" if filter_ is FilterKind.ukf else "kf"
    _record(output, engine, rec, lmp, method.value, kind, sigma, hs, threshold, candidates, calibration)


def _record_or_study(
    source: str, example: ExampleKind | None, record: dict[str, Any], db_convention: str, study: bool,
    calibrate: bool, threshold: float | None, pfa: float | None, candidates: bool, null_trials: int | None,
) -> VehicleRecord | None:  # fmt: skip
    """The record (None for --montecarlo and --calibrate, ``study``), after the checks of the options that
    apply to a record only or to a study only (``record``: the record options by field)."""
    record_opts = [opt for opt, key in RECORD_OPTIONS.items() if record[key] is not None]
    if study:
        not_mc = [opt for opt in record_opts if opt not in MODEL_OPTIONS]
        _refuse_record_options(not_mc + (["--threshold"] if threshold is not None else []), calibrate)
        if example is ExampleKind.two_d and record_opts:
            raise typer.BadParameter(
                "applies to a record or the 1d Monte Carlo (--montecarlo --example 2d simulates Fig 7's "
                "vehicle)",
                param_hint=record_opts[0],
            )
    else:
        for opt in record_opts:
            if opt in RECORD_ONLY:
                raise typer.BadParameter(
                    "describes a simulated truth (simulate, --montecarlo, --calibrate); on a record the "
                    "filters search the carrier: --fd-grid or --fc-grid",
                    param_hint=opt,
                )
        if pfa is not None and threshold is not None:
            raise typer.BadParameter(
                "calibrates a threshold: give --pfa or --threshold, not both", param_hint="--pfa"
            )
        if pfa is not None and candidates:
            raise typer.BadParameter("decides on the argmax: not with --candidates", param_hint="--pfa")
        if null_trials is not None and pfa is None:
            raise typer.BadParameter("applies with --pfa (or --calibrate)", param_hint="--null-trials")
        return _read_record(source, example, record, db_convention)
    return None


def _check_method(method: Any, filter_: Any, two_d: bool) -> None:
    """--method linearised is the 2d example's; --method fft replaces the filter bank."""
    if method is Method.linearised and not two_d:
        raise typer.BadParameter("applies to the 2d example only (1d: bank or fft)", param_hint="--method")
    if method is Method.fft and filter_ is FilterKind.ukf:
        raise typer.BadParameter(
            "the FFT path replaces the filter bank: drop --filter ukf", param_hint="--method"
        )


def _study(
    output: Output, engine: Engine, lmp: dict[str, Any], mc: tuple[Any, ...], model: dict[str, Any],
    filter_: FilterKind, fr_list: str | None, calibrate: bool, pfa: float | None, null_trials: int | None,
    signature: bool, detector: Any,
) -> None:  # fmt: skip
    """The 1d --calibrate or --montecarlo (``mc``: R list, horizons, trials, seed, method)."""
    if calibrate:
        return _calibrate(output, engine, lmp, _floats("--fr-list", fr_list or "0.01", "frequency"), *mc,
                          null_trials, 0.01 if pfa is None else pfa, model, detector)  # fmt: skip
    if pfa is not None or null_trials is not None:
        hint = "--pfa" if pfa is not None else "--null-trials"
        raise typer.BadParameter("applies to a record or --calibrate, not --montecarlo", param_hint=hint)
    frs = _floats("--fr-list", fr_list or "0.01,0.1,1.0", "frequency")
    return _montecarlo(output, engine, lmp, filter_, frs, *mc, signature, model)


def _floats(option: str, text: str | None, what: str) -> tuple[float, ...] | None:
    """A comma-separated option as numbers (None when not given); bad text is a usage error."""
    return None if text is None else tuple(common.checked(option, common.float_list, text, what=what))


def _carriers(
    fc_grid: str | None, fd_grid: str | None, f_c: float, fc_given: bool
) -> tuple[float, ...] | None:
    """The candidate carriers: --fc-grid, or f_c + each offset of --fd-grid (a list or lo:hi:n), or the
    Monte Carlo's --fc alone; None: the configuration's default (the known f_c)."""
    if fd_grid is None:
        grid = _floats("--fc-grid", fc_grid, "frequency")
        return (f_c,) if grid is None and fc_given else grid
    if fc_grid is not None:
        raise typer.BadParameter(
            "is an offset grid around f_c: give --fc-grid or --fd-grid", param_hint="--fd-grid"
        )
    from motionsig_cli.detection.lmp import carrier_offsets

    text = fd_grid.strip()
    if text.count(":") == 2:
        lo, hi, n = text.split(":")
        offsets = common.checked("--fd-grid", carrier_offsets, _number("--fd-grid", lo),
                                 _number("--fd-grid", hi), _number("--fd-grid", n))  # fmt: skip
    else:
        offsets = _floats("--fd-grid", text, "offset") or ()
    return tuple(f_c + d for d in offsets)


def _number(option: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise typer.BadParameter(
            f"expected lo:hi:n or a list of numbers; got {text!r}", param_hint=option
        ) from None


def _mc_model(record: dict[str, Any], f_c: float) -> dict[str, Any]:
    """The Monte Carlo's vehicle (truth and filters), samples per chip and carrier from the model options
    (``record``: by field; None: simulate's defaults)."""
    from motionsig_cli.models.vehicle import Vehicle1D, pole_placement_gain

    T = 0.05 if record["T"] is None else record["T"]
    if record["K"] is not None:
        gains = _floats("--K", record["K"], "gain")
    else:
        wn = 4 * math.pi if record["wn"] is None else record["wn"]
        gains = pole_placement_gain(T, wn, 0.7 if record["zeta"] is None else record["zeta"])
    loop = {k: record[k] for k in ("a_sig", "a_r", "sigma_a", "f_d", "feedback") if record[k] is not None}
    return dict(vehicle=Vehicle1D(T=T, K=gains, **loop), m_rho=20 if record["m_rho"] is None else record["m_rho"],
                f_c=f_c)  # fmt: skip


def _given(**values: Any) -> dict[str, Any]:
    """The values that are not None (the others keep the configuration's defaults)."""
    return {k: v for k, v in values.items() if v is not None}


def _read_record(
    source: str, example: ExampleKind | None, record: dict[str, Any], db_convention: str
) -> VehicleRecord:
    """The record named by SOURCE, with the model the filters assume (``record``: the record options by
    field; the metadata, or the columns, say which example it is; --example forces it)."""
    from motionsig_cli.modesig.record_reading import ModelOptions, read_vehicle_record

    fields = {k: v for k, v in record.items() if k not in ("columns", "units")}
    fields |= dict(
        K=_floats("--K", record["K"], "gain"), start=_floats("--start", record["start"], "coordinate")
    )
    model = ModelOptions(**fields, db_convention=db_convention)
    kind = None if example is None else example.value
    return read_vehicle_record(
        source, example=kind, columns=record["columns"], units=record["units"], model=model
    )


def _refuse_record_options(given: list[str], calibrate: bool) -> None:
    """Options that describe a record are usage errors with --montecarlo and --calibrate."""
    if given:
        where = "--calibrate" if calibrate else "--montecarlo"
        raise typer.BadParameter(f"applies to a record, not {where}", param_hint=given[0])


def _refuse_for_baseline(detector: Any, calibrate: bool, two_d: bool, given: dict[str, Any]) -> None:
    """--detector estimate-correlate: --calibrate of the 1d example only, and none of the LMP's own options
    (``given``: detect's parameters)."""
    if detector is Detector.lmp:
        return
    if not calibrate or two_d:
        raise typer.BadParameter("applies to --calibrate of the 1d example only", param_hint="--detector")
    lmp_only = {
        "--Qa": given["Qa"] is not None, "--method": given["method"] is not Method.bank,
        "--Ar": given["Ar_"] is Ar.known, "--weights": given["weights"] is not Weights.paper,
        "--center": given["center"] is not Center.none, "--q-model": given["q_model"] is not QModel.per_step,
        "--include-logdet": given["include_logdet"], "--filter": given["filter_"] is FilterKind.ukf,
    }  # fmt: skip
    for option, is_given in lmp_only.items():
        if is_given:
            raise typer.BadParameter(
                "is an LMP setting: not with --detector estimate-correlate", param_hint=option
            )


def _preset(
    preset: Preset, two_d: bool, c_r: float | None, Q0: str | None, Qa: float | None
) -> tuple[float, str | None, float | None]:
    """--c-r, --Q0 and --Qa after ``--preset``: the given values, else the preset's, else the defaults
    (c_r = 100; Q0 and Q_a None: eqs 56-57 as printed, or Q_a = 0 on the FFT path)."""
    if preset is Preset.paper:
        if two_d:
            raise typer.BadParameter("is a reading of the 1d example (Figs 4-6)", param_hint="--preset")
        from motionsig_cli.modesig.lmp_search import PAPER_READING

        c_r = PAPER_READING.c_r if c_r is None else c_r
        Q0 = ",".join(f"{q:g}" for q in PAPER_READING.Q0) if Q0 is None else Q0
        Qa = PAPER_READING.Q_a if Qa is None else Qa
    return (100.0 if c_r is None else c_r), Q0, Qa


def _refuse_other_example(two_d: bool, given: dict[str, bool]) -> None:
    """An option of the other example (given: option → whether it was given) is a usage error."""
    only_1d = ("--Qa", "--method", "--calibrate", "--Ar", "--weights", "--center", "--R-list", "--q-model")
    for option, was_given in given.items():
        if was_given and (option in only_1d) == two_d:
            raise typer.BadParameter(
                f"applies to the {'1d' if two_d else '2d'} example only", param_hint=option
            )


def _record(
    output: Output, engine: Engine, rec: VehicleRecord | None, lmp: dict[str, Any], method: str, kind: str,
    sigma: SigmaPointParams, hs: tuple[float, ...] | None, threshold: float | None, candidates: bool,
    calibration: tuple[float, int | None, int] | None,
) -> None:  # fmt: skip
    """Eq (52) on one 1-D record, with a progress bar of the bank's time steps; with ``calibration``
    (pfa, null trials, seed) at a threshold calibrated on null records first."""
    from motionsig_cli.cli.records import emit_record, with_null_threshold
    from motionsig_cli.detection.lmp import LMPConfig
    from motionsig_cli.modesig.lmp1d import RecordDetection

    assert rec is not None
    cfg = LMPConfig(**{"fc_grid": (rec.f_c,), **lmp})
    run = RecordDetection(rec, cfg, method, kind, sigma, hs, threshold, candidates)
    if calibration is not None:
        run = with_null_threshold(run, method, kind, sigma, *calibration, engine, output)
    with progress_bar("LMP filter bank (time steps)", run.steps, output.quiet) as advance:
        result = run.detect(progress=advance)
    emit_record(output, result, run.title)


def _montecarlo(
    output: Output, engine: Engine, lmp: dict[str, Any], filter_: FilterKind, frs: tuple[float, ...] | None,
    Rs: tuple[float, ...] | None, hs: tuple[float, ...] | None, trials: int, seed: int, method: str,
    signature: bool, model: dict[str, Any],
) -> None:  # fmt: skip
    """Figs 4–6: % correct (i, τ) vs horizon and ANR."""
    from motionsig_cli.detection.lmp import LMPConfig
    from motionsig_cli.modesig.lmp1d import LmpJob

    if filter_ is FilterKind.ukf:
        raise typer.BadParameter(
            "the 1d Monte Carlo runs the Kalman bank (the sigma-point bank gives the same numbers at ~20x the "
            "cost); use it on single records",
            param_hint="--filter",
        )
    job = LmpJob(LMPConfig(**lmp), frs, Rs, hs, trials, seed, signature, method, **model)
    mc = common.run_job(job, engine, "Monte Carlo trials", output.quiet)
    output.result(mc, "montecarlo_figure")


def _calibrate(
    output: Output, engine: Engine, lmp: dict[str, Any], frs: tuple[float, ...] | None,
    Rs: tuple[float, ...] | None, hs: tuple[float, ...] | None, trials: int, seed: int, method: str,
    null_trials: int | None, pfa: float, model: dict[str, Any], detector: Any = None,
) -> None:  # fmt: skip
    """The threshold of max Λ for a false-alarm probability, and P_D at it (ROC curves with --plot); with
    ``detector`` estimate-correlate, the baseline's (:mod:`motionsig_cli.modesig.baseline_calibration`)."""
    from motionsig_cli.detection.lmp import LMPConfig
    from motionsig_cli.modesig.lmp1d import CalibrationJob

    if detector is Detector.estimate_correlate:
        from motionsig_cli.modesig.baseline_calibration import baseline_calibration_job

        job: Any = baseline_calibration_job(lmp, frs, Rs, hs, trials, null_trials, pfa, seed, model)
    else:
        job = CalibrationJob(LMPConfig(**lmp), frs, Rs, hs, trials, null_trials, pfa, seed, method, **model)
    if job.warning:
        output.note(job.warning)
    cal = common.run_job(job, engine, "Calibration trials (null + signature)", output.quiet)
    output.result(cal, "calibration_roc_figure")
