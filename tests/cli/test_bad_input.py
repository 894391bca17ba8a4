"""Bad input of every command, in one table: each case is refused with exit code 2, nothing on stdout and a
one-line message without a traceback that names the option (or the file and line) at fault, and no file is
written. The rows come from the commands' own test files; the helpers that build a row say what else a case
checks (a message's start, the files a case reads)."""

from typing import NamedTuple

import pytest

from tests.cli.helpers import MC_1D, one_line_error

TMP = "{tmp}"  # replaced by the case's tmp_path
OUT = ("-o", f"{TMP}/o.csv")


class Case(NamedTuple):
    """``motionsig *args`` fails; every needle is in the message, which starts with ``start``; ``files``
    (name, text) are written to tmp_path first and are all that is there afterwards; a ``plain`` message has
    no validator wording."""

    args: tuple[str, ...]
    needles: tuple[str, ...]
    start: str = "motionsig "
    files: tuple[tuple[str, str], ...] = ()
    plain: bool = False  # no pydantic-style validator wording ("Input should be ...")


# --- detect ------------------------------------------------------------------------------------------------

MC_1D_SMALL = (
    "detect",
    "--montecarlo",
    "--trials",
    "1",
    "--fr-list",
    "0.01",
    "--R-list",
    "1",
    "--horizons",
    "1",
)
MC_2D_SMALL = (
    "detect",
    "--montecarlo",
    "--example",
    "2d",
    "--trials",
    "1",
    "--anr-pairs",
    "4",
    "--horizons",
    "1",
)
CAL_SMALL = (
    "detect",
    "--calibrate",
    "--method",
    "fft",
    "--trials",
    "1",
    "--null-trials",
    "2",
    "--R-list",
    "1",
    "--horizons",
    "1",
)

DETECT_ENGINE = [
    (("--workers", "0"), "--workers"),
    (("--workers", "100000"), "--workers"),
    (("--scheduler", "nowhere"), "--scheduler"),
    (("--scheduler", ""), "--scheduler"),
]
# a ConfigError of the configurations (the CLI checks no range itself) is one line naming the option
DETECT_CORE = [
    ((*MC_1D_SMALL, "--trials", "0"), "--trials", "0 is not in [1, inf]"),
    ((*MC_1D_SMALL, "--fr-list=-1"), "--fr-list", "-1 is not in [0, inf) Hz"),
    ((*MC_1D_SMALL, "--R-list", "0"), "--R-list", "0 is not a finite number > 0"),
    ((*MC_1D_SMALL, "--horizons", "0.02"), "--horizons", "shorter than one sample"),
    ((*MC_1D_SMALL, "--c-r", "0"), "--c-r", "> 0"),
    ((*MC_1D_SMALL, "--P0", "-1"), "--P0", "> 0"),
    ((*MC_1D_SMALL, "--Qa=-1"), "--Qa", "PSD"),
    ((*MC_1D_SMALL, "--Q0", "1,1,1"), "--Q0", "4 variances"),
    ((*MC_1D_SMALL, "--Q0", "1,1,-1,1"), "--Q0", "PSD"),
    ((*MC_1D_SMALL, "--fc-grid=-1"), "--fc-grid", "-1 is not in [0, inf) Hz"),
    ((*MC_1D_SMALL, "--method", "fft", "--zdot", "finite-difference"), "--method", "analytic"),
    ((*CAL_SMALL, "--pfa", "0"), "--pfa", "0 is not in (0, 1)"),
    ((*CAL_SMALL, "--null-trials", "0"), "--null-trials", "0 is not in [1, inf]"),
    ((*CAL_SMALL, "--trials", "3000000"), "--trials", "at most"),
    ((*MC_2D_SMALL, "--anr-pairs", "5"), "--anr-pairs", "is not one of 1, 2, 3, 4"),
    ((*MC_2D_SMALL, "--horizons", "2e6"), "--horizons", "is not in [0.05, 1e+06] s"),
    ((*MC_2D_SMALL, "--fr-list", "2e6"), "--fr-list", "is not in [0, 1e+06] Hz"),
    ((*MC_2D_SMALL, "--Q1", "1,2"), "--Q1", "10 variances"),
    ((*MC_2D_SMALL, "--Q0", "1,2"), "--Q0", "8 variances"),
    ((*MC_2D_SMALL, "--kappa=-9"), "--kappa", "<= 0"),
    ((*MC_2D_SMALL, "--alpha", "1e-8"), "--alpha", "centre weight"),
    ((*MC_2D_SMALL, "--beta", "inf"), "--beta", "not a finite number"),
    ((*MC_2D_SMALL, "--trials", "0"), "--trials", "0 is not in [1, inf]"),
]

# --- encode ------------------------------------------------------------------------------------------------

ENCODE = [
    (["encode", "mseq", "--poly", "44"], "--poly", "not primitive"),
    (["encode", "mseq", "--poly", "x^5+y"], "--poly", "malformed"),
    (["encode", "mseq", "--init", "00000"], "--init", "all zeros"),
    (["encode", "mseq", "--init", "0001"], "--init", "'0001' has 4 bits; a degree-5 register needs 5 bits"),
    (["encode", "pairs", "--degree", "8"], "--degree", "8 is a multiple of 4"),
    (["encode", "pairs", "--degree", "5,15"], "--degree", "15 is > 13"),
    (["encode", "pairs", "--degree", "2"], "--degree", "2 is < 3"),
    (
        ["encode", "gold", "--poly1", "45", "--poly2", "51"],
        "--poly2",
        "'51' is not a preferred partner of 45",
    ),
    (
        ["encode", "gold", "--poly1", "x^8+x^4+x^3+x^2+1", "--poly2", "x^8+x^6+x^5+x^3+1"],
        "--poly1",
        "has degree 8, which is a multiple of 4",
    ),
    (["encode", "gold", "--poly1", "45", "--poly2", "x^6+x+1"], "--poly2", "not the degree 5 of poly1"),
    (["encode", "gold", "--index", "40"], "--index", "40 is not in [-2, 30]"),
    (["encode", "gold", "--init2", "00000"], "--init2", "all zeros"),
    (["encode", "gold", "--unchecked", "--poly2", "44"], "--poly2", "not primitive"),
    (["encode", "check-pair", "--poly1", "44", "--poly2", "45"], "--poly1", "not primitive"),
    (["encode", "check-pair", "--poly1", "45", "--poly2", "x^6+x+1"], "--poly2", "not the degree 5"),
    (["encode", "signature", "--T", "0"], "--T", "positive"),
    (["encode", "signature", "--T", "-0.1"], "--T", "positive"),
    (["encode", "signature", "--mrho", "0"], "--mrho", "integer >= 1"),
    (["encode", "signature", "--fc", "-1"], "--fc", "-1 is not in [0, inf)"),
    (["encode", "signature", "--fd", "nan"], "--fd", "nan is not a finite number"),
    (["encode", "signature", "--theta", "abc"], "--theta", "radians"),
    (["encode", "signature", "--theta", "inf"], "--theta", "finite"),
    (["encode", "signature", "--mode", "4"], "--mode", "4 is not a Table I mode (1, 2, 3)"),
    (["encode", "gps", "--prn", "33"], "--prn", "33 is not in [1, 32]"),
    (["encode", "gps", "--prn", "0"], "--prn", "0 is not in [1, 32]"),
    (["encode", "gps", "--prn", "x"], "--prn", "expected a PRN"),
    (["encode", "pairs", "--degree", "3-x"], "--degree", "expected a degree"),
    (["encode", "signature", "--plot", "x.gif"], "--plot", "unsupported"),
    (["encode", "mseq", "--shift", "abc"], "--shift", "valid integer"),
    (["encode", "mseq", "--poly", "x^25+x^3+1"], "--poly", "degree 25 > 20"),
    (["encode", "pairs", "--degree", "1-1000000000"], "--degree", "more than 64"),
    (["encode", "pairs", "--degree", "4-4"], "--degree", "no degree"),
    (["encode", "pairs", "--degree", "1_0"], "--degree", "expected a degree"),
    (["encode", "gps", "--prn", "1-1000000000"], "--prn", "more than 32"),
    (["encode", "mseq", "--init", "\u0660\u0660\u0660\u0660\u0661"], "--init", "only 0 and 1"),
    (
        ["encode", "signature", "--length", "1000000000"],
        "--length",
        "not a number of samples in [1, 5000000]",
    ),
    (["encode", "signature", "--length", "0"], "--length", "not a number of samples in [1, 5000000]"),
    (["encode", "signature", "--mrho", "99999999999"], "--mrho", "samples per code period, more than"),
    (["encode", "signature", "--tau", "99999999999999999999"], "--tau", "2^53"),
    (["encode", "signature", "--T", "1e308"], "--T", "non-finite"),
    (["encode", "table1", "--view", "bogus"], "--view", "'bogus' is not one of"),
    (["encode", "gold", "--all", "--index", "3"], "--all", "drop --index"),
    (["encode", "mseq", "--out", "/nonexistent-dir/x.csv"], "--out", "does not exist"),
]
ENCODE_CSV = [
    ("code,chip\nA,0\n", "missing column 'value'"),
    ("code,chip,value\nA,0,1\nA,1,x\n", "x.csv:3: column 'value'"),
    ("code,chip,value\nA,0,1\nA,1,2\n", "x.csv:3: column 'value': 2 is not a chip"),
    ("code,chip,value\nA,0,1\nA,2,0\n", "chips must be 0..1"),
    ("code,chip,value\nA,0,1\nA,1,-1\nA,2,0\n", "x.csv:4: column 'value': 0 mixes chip conventions"),
    ("code,chip,value\nA,0,1\n", "x.csv:2: code 'A' has 1 chip"),
    ("code,chip,value\nA,99999999999999999999999,1\nA,1,0\n", "x.csv:2: column 'chip'"),
    ('code,chip,value\n"A\nB",0,1\n', "quoted field is not closed on its line"),
    ("code,chip,value\nA,0,1\nA,1,0\nB,0,1\nB,1,0\nB,2,1\n", "different lengths"),
]

# --- jam-bound ---------------------------------------------------------------------------------------------

JAM = [
    (["curves", "--pdl", "1.5"], "--pdl"),
    (["curves", "--pdl", "0"], "--pdl"),
    (["curves", "--K", "0"], "--K"),
    (["curves", "--t", "1"], "--t"),
    (["curves", "--K", "1", "--t", "0.1"], "--t"),
    (["curves", "--B", "0"], "--B"),
    (["curves", "--alpha", "-1"], "--alpha"),
    (["curves", "--beta", "nan"], "--beta"),
    (["curves", "--energy-j", "0"], "--energy-j"),
    (["curves", "--airborne-frac", "1"], "--airborne-frac"),
    (["curves", "--vmax-mph", "1e10"], "--vmax-mph"),
    (["curves", "--figure", "2.17"], "--figure"),
    (["curves", "--step", "0"], "--step"),
    (["curves", "--x-min", "5", "--x-max", "0"], "--x-max"),
    (["curves", "--x-min", "-7000"], "--x-min"),
    (["curves", "--K", "1000", "--x-min", "-20", "--x-max", "80", "--step", "0.0002"], "--step"),
    (["curves", "--figure", "2.4", "--K", "100"], "--K"),
    (["curves", "--figure", "2.4", "--quantity", "nfl"], "--quantity"),
    (["curves", "--pd", "1e-300"], "--pd"),
    (["threshold", "--quantity", "nfl", "--level", "0.9"], "--level"),
    (["threshold", "--B", "1e308"], "--B"),
    (["design", "--K", "1", "--pd", "0.99", "--pdl", "0.5"], "--pdl"),
    (["design", "--K", "100000000000000000000000000000", "--pdl", "0.9", "--t", "0.3"], "--pdl"),
    (["antenna", "--erp-dbw", "33", "--rf-dbw", "40"], "--rf-dbw"),
    (["antenna", "--rf-dbw", "-10000"], "--rf-dbw"),
    (["table", "--which", "1.1", "--freq-hz", "1e-300"], "--freq-hz"),
    (["curves", "--pd", "0.3", "--t", "0.5"], "--t"),
    (["curves", "--pd", "0.9", "--pdl", "0.9"], "--pd"),
    (["threshold", "--level", "1.5"], "--level"),
    (["threshold", "--level", "0"], "--level"),
    (["table", "--eta", "1.5"], "--eta"),
    (["design", "--K", "10"], "--pdl"),
    (["design", "--K", "10", "--pdl", "0.999", "--pd", "0.3"], "--pdl"),
    (["antenna", "--rf-w", "30", "--diameter-ft", "2"], "--diameter-ft"),
    (["antenna", "--diameter-ft", "-2"], "--diameter-ft"),
]
JAM_CONFIG = [
    (["curves", "--B", "0"], "Invalid value for --B: 0 is not a finite number > 0 Hz"),
    (["curves", "--alpha", "inf"], "Invalid value for --alpha: inf is not a finite number > 0 s"),
    (["curves", "--beta", "-1"], "Invalid value for --beta: -1 is not a finite number > 0 s"),
    (
        ["curves", "--vmax-mph", "1e10"],
        "Invalid value for --vmax-mph: 1e+10 is not below the speed of light",
    ),
    (["curves", "--c-mph", "0"], "Invalid value for --c-mph: 0 is not a finite number > 0 mph"),
    (["curves", "--energy-j", "0"], "Invalid value for --energy-j: 0 is not a finite number > 0 J"),
    (["curves", "--airborne-frac", "1"], "Invalid value for --airborne-frac: 1 is not in (0, 1)"),
    (
        ["threshold", "--B", "1e308"],
        "Invalid value for --B/--alpha: inf is not a finite positive sample count",
    ),
    (["curves", "--K", "0"], "Invalid value for --K: 0 is not in [1, inf]"),
    (["threshold", "--K", "0"], "Invalid value for --K: 0 is not in [1, inf]"),
    (["design", "--K", "0", "--pdl", "0.9"], "Invalid value for --K: 0 is not in [1, inf]"),
    (["curves", "--pdl", "0.9,1.5"], "Invalid value for --pdl: 1.5 is not in (0, 1)"),
    (["curves", "--pd", "0"], "Invalid value for --pd: 0 is not in (0, 1)"),
    (["curves", "--t", "1"], "Invalid value for --t: 1 is not in [0, 1)"),
    (["curves", "--pdl", "x"], "Invalid value for --pdl: expected a comma-separated list of numbers"),
    (
        ["curves", "--figure", "2.4", "--K", "100"],
        "Invalid value for --K: 100 is not the K = 10 of Fig. 2.4",
    ),
    (["curves", "--x-min", "-7000"], "Invalid value for --x-min: -7000 is not in [-1000, 1000] dB"),
    (["curves", "--x-min", "5", "--x-max", "0"], "Invalid value for --x-max: 0 is below x_min = 5 dB"),
    (["curves", "--step", "-1"], "Invalid value for --step: -1 is not a finite number > 0 dB"),
    (["threshold", "--level", "0"], "Invalid value for --level: 0 is not in (0, 1]"),
    (["table", "--level", "1.5"], "Invalid value for --level: 1.5 is not in (0, 1]"),
    (["table", "--freq-hz", "-1"], "Invalid value for --freq-hz: -1 is not a finite number > 0 Hz"),
    (["table", "--eta", "1.5"], "Invalid value for --eta: 1.5 is not in (0, 1]"),
    (
        ["antenna", "--rf-w", "30", "--bw-const", "0"],
        "Invalid value for --bw-const: 0 is not a finite number > 0",
    ),
    (
        ["table", "--which", "1.1", "--freq-hz", "1e3"],
        "Invalid value for --freq-hz/--eta/--bw-const: f = 1000 Hz",
    ),
    (
        ["antenna", "--erp-dbw", "inf", "--rf-w", "30"],
        "Invalid value for --erp-dbw: inf is not a finite number",
    ),
    (["antenna", "--rf-dbw", "40"], "Invalid value for --rf-dbw: 40 gives no dish"),
    (["antenna", "--rf-w", "1e5"], "Invalid value for --rf-w: 100000 gives no dish"),
    (["antenna", "--diameter-ft", "0.001"], "Invalid value for --diameter-ft: 0.001 gives no dish"),
    (["antenna", "--rf-w", "0"], "Invalid value for --rf-w: 0 is not a finite number > 0 W"),
]

# --- mac-roc -----------------------------------------------------------------------------------------------

MAC = [
    (("bounds", "--N", "0"), "--N"),
    (("bounds", "--N", "-5"), "--N"),
    (("bounds", "--N", "2.5"), "not an integer"),
    (("bounds", "--tau-over-alpha", "0.7"), "--tau-over-alpha"),
    (("bounds", "--tau-over-alpha", "0"), "--tau-over-alpha"),
    (("bounds", "--density", "cauchy"), "unknown density"),
    (("bounds", "--theta", "0.9:0.1:0.01"), "empty"),
    (("bounds", "--theta", "1.5"), "--theta"),
    (("bounds", "--theta", "0,0.5"), "--theta"),
    (("bounds", "--ell", "-2"), "--ell"),
    (("bounds", "--ell", "8", "--b", "0.1"), "--b"),
    (("bounds", "--figure", "3.9"), "mac-roc exponent"),
    (("bounds", "--figure", "4.2"), "no Fig"),
    (("bounds", "--density", "psk", "--exact"), "--exact"),
    (("exact", "--density", "psk"), "montecarlo"),
    (("montecarlo", "--trials", "0"), "--trials"),
    (("montecarlo", "--density", "psk", "--importance"), "--importance"),
    (("montecarlo", "--density", "psk", "--code", "xyz"), "--code"),
    (("montecarlo", "--density", "psk", "--interferers", "family"), "--interferers"),
    (("bounds", "--density", "uniform", "--ell", "1000", "--theta", "0.9", "--N", "3"), "empty"),
    (("exponent", "--expg", "-1"), "--expg"),
    (("exponent", "--N", "1:1e3:0"), "--N"),
    (("densities", "--figure", "3.3"), "mac-roc bounds"),
    (("bandwidth", "--code", "+2-"), "--code"),
    (("montecarlo", "--workers", "0", "--trials", "1000"), "--workers"),
    (("montecarlo", "--importance", "--workers", "-1", "--trials", "1000"), "--workers"),
    (("bounds", "--montecarlo", "1000", "--workers", "0"), "--workers"),
    (("bounds", "--theta", "0.5", "--checkpoint", "ckpt"), "--checkpoint"),
    (
        (
            "montecarlo",
            "--ell",
            "8",
            "--theta",
            "0.5",
            "--trials",
            "1000",
            "--scheduler",
            "tcp://127.0.0.1:1",
        ),
        "--scheduler",
    ),
]
# found by the adversarial review: N = 1 crashed, tiny tau/alpha gave a false 'lower bound' 0.5, and an
# explicit two-point density was silently replaced by a figure's density
MAC_REVIEW = [
    (("bounds", "--N", "1", "--theta", "0.5"), "has no interferers"),
    (("gaussian", "--N", "1", "--theta", "0.5"), "has no interferers"),
    (("bounds", "--tau-over-alpha", "1e-70", "--theta", "0.5"), "1e-50"),
    (("bounds", "--figure", "3.3", "--density", "two-point"), "uniform density"),
]
# the core's ConfigError names the configuration field; the command line names its option
MAC_CONFIG = [
    (("bounds", "--at-pd", "1.5"), "Invalid value for --at-pd: 1.5 is not in (0, 1)"),
    (("bounds", "--density", "psk", "--ell", "8"), "Invalid value for --ell: (8.0,) is not used"),
    (("bounds", "--montecarlo", "1e3", "--at-pd", "0.9"), "Invalid value for --montecarlo: 1000 needs"),
    (("bounds", "--b", "0"), "Invalid value for --b: 0 is not a finite number > 0"),
    (("bounds", "--N", "1e16"), "Invalid value for --N: 1e+16 is not in [1, 1000000000000000]"),
    (("bounds", "--N", "inf"), "Invalid value for --N: inf is not an integer"),
    (("bounds", "--N", "many"), "Invalid value for --N: expected a number"),
    (
        ("bounds", "--density", "psk", "--code", "gold:45,75:99"),
        "Invalid value for --code: 'gold:45,75:99'",
    ),
    (("bounds", "--theta", "0.2:0.8"), "Invalid value for --theta: expected start:stop:step"),
    (("montecarlo", "--density", "arcsine", "--importance"), "Invalid value for --importance: True"),
    (("montecarlo", "--trials", "1e11"), "Invalid value for --trials: 1e+11 is not in [1, 10000000000]"),
    (("montecarlo", "--seed", "-1", "--trials", "10"), "--seed"),
    (("exact", "--density", "arcsine"), "Invalid value for --density: 'arcsine' has no exact ROC"),
    (
        ("gaussian", "--figure", "3.3"),
        "Invalid value for --figure: '3.3' is drawn by `motionsig mac-roc bounds`",
    ),
    (("gaussian", "--gauss-variance", "M"), "--gauss-variance"),
    (
        ("exponent", "--tau-over-alpha", "0.6"),
        "Invalid value for --tau-over-alpha: 0.6 is not in (0, 0.5)",
    ),
    (("exponent", "--N", "1"), "Invalid value for --N: 1 is not in (1, inf)"),
    (
        ("exponent", "--expg", "0:1e6:100000", "--N", "1e3:1e6:100"),
        "Invalid value for --expg: 100000 gives",
    ),
    (("densities", "--b", "0"), "Invalid value for --b: 0 is not a finite number > 0"),
    (
        ("densities", "--figure", "3.8"),
        "Invalid value for --figure: '3.8' is drawn by `motionsig mac-roc gaussian`",
    ),
    (("bandwidth", "--alpha", "0"), "Invalid value for --alpha: 0 is not a finite number > 0 s"),
    (("bandwidth", "--tau-c", "-1"), "Invalid value for --tau-c: -1 is not a finite number > 0 s"),
    (("bandwidth", "--N", "0"), "Invalid value for --N: 0 is not in [1, 1000000000000000]"),
    (("bandwidth", "--code", ";"), "Invalid value for --code: '' names no code"),
]

# --- maneuver ----------------------------------------------------------------------------------------------

MAN = [
    (("--sigma", "0"), "Invalid value for --sigma: 0 is not in [0.001, 1e+07] m"),
    (("--sigma", "-5,100"), "--sigma"),
    (("--sigma", "1e-300"), "--sigma"),
    (("--transition", "0.9,0.05,0.05;0.025,0.95,0.025;0.025,0.025,0.9"), "row 3"),
    (("--transition", "1.1,-0.05,-0.05;0.025,0.95,0.025;0.025,0.025,0.95"), "row 1"),
    (("--transition", "0.5,0.5;0.5,0.5"), "3 rows of 3"),
    (("--mu0", "0.8,0.1,0.2"), "--mu0"),
    (("--window", "0"), "Invalid value for --window: 0 is not in [1, 200]"),
    (("--method", "imm,kalman"), "Invalid value for --method: 'kalman' is not one of imm, glr, mlr, cv"),
    (("--plot-compare", "x.png"), "two methods"),
    (("--view", "events"), "glr or mlr"),
    (("--runs", "1000000", "--method", "all"), "estimated"),
    (("--glr-threshold", "nan"), "--glr-threshold"),
    (("--glr-threshold", "-1"), "Invalid value for --glr-threshold: -1 is not a finite number >= 0"),
    (("--T", "1e-300"), "--T"),
    (("--T", "3601"), "Invalid value for --T: 3601 is not in [0.001, 3600] s"),
    (("--q0", "nan"), "--q0"),
    (("--mlr-sigma-u", "1e160"), "Invalid value for --mlr-sigma-u: 1e+160 is not in [0.001, 1e+06] m/s²"),
    (("--q0", "1e7"), "Invalid value for --q0: 1e+07 is not in [0, 1e+06] m²/s³"),
    (("--mlr-threshold", "inf"), "Invalid value for --mlr-threshold: inf is not in (-inf, inf)"),
    (("--scans", "2"), "Invalid value for --scans: 2 is not in [3, 100000]"),
    (("--runs", "0"), "Invalid value for --runs: 0 is not in [1, 1000000]"),
    (("--response", "0"), "Invalid value for --response: 0 is not in [1, 10000]"),
    (("--sigma", ",".join(str(10 * i) for i in range(1, 12))), "Invalid value for --sigma"),
    (("--transition", "1,0;0,1"), "Invalid value for --transition"),
    (("--mu0", "0.5,0.5"), "Invalid value for --mu0: [0.5, 0.5] is not 3 probabilities"),
    (("--sigma", "1e-3", "--T", "3600", "--scans", "240"), "--sigma: 0.001 m is too small"),
    (("--view", "measurements", "--plot", "m.png"), "draws no figure"),
]
MAN_REC = [
    ("1,0,0\n2.5,0,450\n3,0,900\n", "bad.csv:4: column 'scan': '2.5' is not an integer"),
    ("1,0,0\n2,0,450\n3,nan,900\n", "bad.csv: need at least 3 scans with a measurement"),
    ("1,0,0\n2,0,450\n3,inf,900\n", "not finite"),
    ("1,0,0\n2,0,450\n", "at least 3 scans"),
    ("1,0,0\n2,0,450\n-,0,900\n", "bad.csv:5: column 'scan': missing value is not an integer"),
    ("1,0,0\n2,abc,450\n3,0,900\n", "bad.csv:4"),
    ("1,0,0\n2,1e308,450\n3,0,900\n", "bad.csv:4: column 'z_x': |measurement| 1e+308 m exceeds"),
]
MAN_META = [
    (("--sigma", "0"), "", "Invalid value for --sigma: 0 is not in [0.001, 1e+07] m"),
    (("--sigma", "100,200"), "", "Invalid value for --sigma: give one σ with a record"),
    (("--T", "0"), "# sigma: 100\n", "Invalid value for --T: 0 is not in [0.001, 3600] s"),
    ((), "# sigma: 1e8\n", "r.csv: metadata 'sigma' = 1e+08 is not in [0.001, 1e+07] m"),
    ((), "# sigma: 100\n# T: 7200\n", "r.csv: metadata 'T' = 7200 is not in [0.001, 3600] s"),
    ((), "# sigma: -1\n", "r.csv: metadata 'sigma' must be a finite number > 0"),
    (("--method", "ckf"), "# sigma: 100\n", "Invalid value for --method: 'ckf' is not one of"),
    (("--view", "summary"), "# sigma: 100\n", "the per-step track (scans) or its declarations (events)"),
]
MAN_BODY = "scan,z_x,z_y\n1,0,0\n2,0,450\n3,0,900\n"

# --- simulate ----------------------------------------------------------------------------------------------

SIM = [
    (["--tau", "1", "--tau-chips", "2"], "--tau-chips", "not both"),
    (["--tau", "9007199254740993"], "--tau", "2^53"),
    (["--tau-chips", "1125899906842624"], "--tau-chips", "2^53"),
    (["--mrho", "0"], "--mrho", "integer >= 1"),
    (["--fc", "-1"], "--fc", "is not in [0, inf)"),
    (["--a-sig", "-1"], "--a-sig", "is not in [0, inf)"),
    (["--a-r", "nan"], "--a-r", "is not in [0, inf)"),
    (["--f-r", "-0.1"], "--f-r", "is not in [0, inf)"),
    (["--sigma-a", "-1"], "--sigma-a", "is not in [0, inf)"),
    (["--pole-wn", "0"], "--pole-wn", "> 0"),
    (["--pole-zeta", "1"], "--pole-zeta", "is not in (0, 1)"),
    (["--T", "1e-300"], "--T", "pole placement"),
    (["--T", "inf"], "--T", "> 0"),
    (["--K", "1,nan"], "--K", "finite"),
    (["--theta", "inf"], "--theta", "not a finite number"),
    (["--theta", "abc"], "--theta", "could not convert"),
    (["--zdot", "foo"], "--zdot", "is not one of analytic, finite-difference"),
    (["--duration", "1e6"], "--duration", "more than 1000000"),
    (["--duration", "0.01"], "--duration", "shorter than one sample"),
    (["--anr-db", "nan"], "--anr-db", "not a finite number"),
    (["--anr-db", "1e6"], "--anr-db", "too large"),
    (["--a-sig", "0", "--anr-db", "40"], "--a-sig", "is not > 0"),
    (["--K", "1e9,1e9", "--duration", "20"], "--K", "unstable"),
    (["--R-range", "1"], "--R-range", "applies to --example 2d only"),
    (["--R-bearing", "1"], "--R-bearing", "applies to --example 2d only"),
    (["--anr-pair", "2"], "--anr-pair", "applies to --example 2d only"),
    (["--start", "1,2"], "--start/--sig-axes", "applies to --example 2d only"),
    (["--sig-axes", "x"], "--start/--sig-axes", "applies to --example 2d only"),
    (["--example", "2d", "--R", "1e-3"], "--R", "applies to --example 1d"),
    (["--example", "2d", "--anr-db", "40"], "--anr-db", "applies to --example 1d"),
    (["--example", "2d", "--anr-pair", "5"], "--anr-pair", "ANR pairs 1-4"),
    (["--example", "2d", "--anr-pair", "2", "--R-range", "1e-3"], "--anr-pair", "not both"),
    (["--example", "2d", "--R-range", "0", "--R-bearing", "1e-3"], "--R-range", "> 0"),
    (["--example", "2d", "--R-range", "1e-3", "--R-bearing", "-1"], "--R-bearing", "> 0"),
    (["--example", "2d", "--a-sig", "0"], "--a-sig", "is not > 0"),
    (["--example", "2d", "--start", "0,0"], "--start", "origin"),
    (["--example", "2d", "--start", "1,2,3"], "--start", "two finite coordinates"),
    (["--example", "2d", "--start", "a,b"], "--start", "comma-separated"),
    (
        ["--example", "2d", "--R-range", "100", "--R-bearing", "1e-3", "--duration", "3"],
        "--R-range",
        "radar",
    ),
    (["--example", "2d", "--start", "-5,-5", "--duration", "60"], "--start", "too close to the radar"),
    (["--example", "2d", "--K", "1e9,1e9", "--duration", "20"], "--K", "unstable"),
]
SIMDET_SIM = [
    (["--R", "0"], "--R", "> 0"),
    (["--R", "-1e-3"], "--R", "> 0"),
    (["--mode", "4"], "--mode", "not a Table I mode: 1, 2 or 3"),
    (["--T", "0"], "--T", "> 0"),
    (["--duration", "-5"], "--duration", "> 0"),
    (["--K", "1,2,3"], "--K", "two finite gains"),
    (["--R", "1e-3", "--anr-db", "40"], "--anr-db", "not both"),
    (["--montecarlo"], "No such option", ""),
]
SIM_2D = [
    (("--R", "1e-3"), "--R"),
    (("--anr-pair", "5"), "--anr-pair"),
    (("--anr-pair", "2", "--R-range", "1e-3"), "--anr-pair"),
    (("--start", "0,0"), "--start"),
    (("--start", "1,2,3"), "--start"),
    (("--R-bearing", "-1"), "--R-bearing"),
]

# --- slrt --------------------------------------------------------------------------------------------------

SLRT = [
    (("--pd", "0"), "--pd"),
    (("--pd", "1.5"), "--pd"),
    (("--filter-pd", "0"), "--filter-pd"),
    (("--clutter", "-1"), "--clutter"),
    (("--alpha", "0.5"), "--alpha"),
    (("--beta", "0"), "--beta"),
    (("--sensors", "0"), "--sensors"),
    (("--radius", "0"), "--radius"),
    (("--sigma-r", "0"), "--sigma-r"),
    (("--sigma-phi-deg", "-1"), "--sigma-phi-deg"),
    (("--methods", "ukf"), "--methods"),
    (("--runs", "100000", "--scans", "1000"), "--runs"),
    (("--pd", "1", "--target-only"), "--pd"),
    (("--runs", "1", "--scans", "100000"), "--runs"),
    (("--radius", "30000"), "--radius"),
    (("--sensors", "3", "--radius", "1e-200"), "--radius"),
    (("--sigma-r", "1e-170"), "--sigma-r"),
    (("--T", "1e300"), "--T"),
    (("--q", "inf"), "--q"),
    (("--plot-scan", "same.png", "-o", "same.png"), "--plot-scan"),
    (("--plot", "b.png", "--plot-scan", "b.png"), "--plot-scan"),
    (("--plot-scan", "x.xyz"), "--plot-scan"),
    (("--sensors", "65"), "--sensors"),
    (("--clutter", "1001"), "--clutter"),
    (("--scans", "0"), "--scans"),
    (("--T", "0"), "--T"),
    (("--q", "-1"), "--q"),
    (("--sigma-phi-deg", "91"), "--sigma-phi-deg"),
    (("--filter-pd", "1"), "--filter-pd"),
    (("--pd", "0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,0.95,0.99"), "--pd"),
    (("--methods", ","), "--methods"),
    (("--runs", "0"), "--runs"),
]
SLRT_CORE = [
    (("--sigma-r", "0"), "--sigma-r: 0 is not in [0.001, 100000] m"),
    (("--sensors", "0"), "--sensors: 0 is not in [1, 64]"),
    (("--clutter", "-1"), "--clutter: -1 is not in [0, 1000]"),
    (("--radius", "30000"), "--radius: 30000 is not in [0, 26000) m"),
    (("--alpha", "0.5"), "--alpha: 0.5 is not in (0, 0.5)"),
    (("--pd", "1.5"), "--pd: 1.5 is not in (0, 1]"),
    (("--methods", "ckf,ukf"), "--methods: 'ukf' is not one of ckf, dkf, fkf, fkf-feedback, lkf, ldf, naive"),
    (("--runs", "100000"), "--runs: 100000 is too many runs for 6 case(s) x 30 scans x 4 sensors"),
]

# --- track-sat ---------------------------------------------------------------------------------------------

TINY_SIM = ("--runs", "2", "--epochs", "4", "--outage-start", "2", "--outage-length", "1")
TRACK = [
    (("rms", "--sigma", "0"), "--sigma"),
    (("rms", "--sigma", "-5"), "--sigma"),
    (("rms", "--sigma0", "5,-1"), "--sigma0"),
    (("rms", "--outage-length", "100"), "longer than the run"),
    (("rms", "--epochs", "50"), "longer than the run"),
    (("constellation", "--aircraft", "95,120"), "--aircraft"),
    (("constellation", "--outage-sats", "1,2"), "--outage-sats"),
    (("constellation", "--outage-sats", "1,2,9"), "--outage-sats"),
    (("constellation", "--rsat-km", "6000"), "--rsat-km"),
    (("constellation", "--rsat-km", "50000", "--rsat-re", "8"), "not both"),
    (("simulate", "--runs", "0"), "--runs"),
    (("simulate", "--rho", "0.4"), "--rho"),
    (("simulate", "--estimators", "ukf"), "--estimators"),
    (("simulate", "--velocity-enu", "1,2"), "--velocity-enu"),
    (("psi", "--alpha", "-1"), "--alpha"),
    (("psi", "--grid", "1:0.1:5"), "--grid"),
    (("table", "--which", "4.4"), "--which"),
    (("table", "--which", "4.2", "--convention", "report"), "--which"),
    (("rms", "--epochs", "1000000", "--outage-length", "0"), "--epochs"),
    (("rms", "--sigma", "1e300"), "--sigma"),
    (("rms", "--convention", "report", "--rsat-re", "8"), "--params geometry"),
    (("rms", "--rsat-re", "1.001", "--params", "geometry"), "--rsat-re"),
    (("simulate", "--sigma0", "inf"), "--sigma0"),
    (("simulate", "--runs", "50000", "--epochs", "5000"), "--runs"),
    (("simulate", "--velocity-enu", "1e300,0,0"), "--velocity-enu"),
    (("simulate", "--velocity-enu", "0,0,-100", "--runs", "2"), "--velocity-enu"),
    (("constellation", "--aircraft", "45,120,-6000"), "--aircraft"),
    (("constellation", "--aircraft", "-45,-60"), "--aircraft"),
    (("constellation", "--outage-sats", "1,2,3,3"), "--outage-sats"),
    (("simulate", "--workers", "0"), "--workers"),
    (("simulate", "--scheduler", " "), "--scheduler"),
    (("simulate", *TINY_SIM, "-q", "--scheduler", "tcp://127.0.0.1:1"), "--scheduler"),  # unreachable
    (("rms", "--epochs", "-1", "--outage-length", "0"), "--epochs"),
    (("rms", "--outage-start", "-1"), "--outage-start"),
    (("rms", "--outage-length", "-1"), "--outage-length"),
    (("rms", "--sigma0", ",".join(["5"] * 21)), "--sigma0"),
    (("rms", "--rsat-km", "5e6", "--params", "geometry"), "--rsat-km"),
    (("constellation", "--rsat-re", "1.001"), "--rsat-re"),
    (("constellation", "--aircraft", "45,120,1,2"), "--aircraft"),
    (("constellation", "--aircraft", "45,1000"), "--aircraft"),
    (("constellation", "--rsat-km", "7000"), "--rsat-km/--rsat-re"),  # satellites below the horizon
    (("simulate", "--sigma", "0"), "--sigma"),
    (("simulate", "--sigma0", "-1"), "--sigma0"),
    (("simulate", "--runs", "50001"), "--runs"),
    (("simulate", "--estimators", ","), "--estimators"),
    (("simulate", "--outage-sats", "1,2,2"), "--outage-sats"),
    (("simulate", "--rsat-km", "6000"), "--rsat-km"),
    (("simulate", "--epochs", "5001", "--rho", "0.9", "--runs", "1"), "--rho"),
    (("psi", "--grid", "1:2"), "--grid"),
    (("psi", "--grid", "0:2:5"), "--grid"),
    (("table", "--which", "4.2", "--params", "table"), "--which"),
]
# the core's ConfigError, mapped to the option: no pydantic-style 'Input should be ...' wording
TRACK_CONFIG = [
    (("rms", "--sigma", "0"), "--sigma", "0 is not in (0, 1e+09] ns"),
    (("rms", "--sigma0", "5,-1"), "--sigma0", "-1 is not in [0, 1e+09] ns"),
    (("rms", "--epochs", "1000000", "--outage-length", "0"), "--epochs", "1000000 is not in [0, 100000]"),
    (("simulate", "--runs", "0"), "--runs", "0 is not in [1, 50000]"),
    (("simulate", "--rho", "0.4"), "--rho", "0.4 is not in (0.5, 1]"),
    (("simulate", "--estimators", "ukf"), "--estimators", "'ukf' is not one of none, report, kf2"),
    (("constellation", "--rsat-km", "6000"), "--rsat-km", "6000 is not in (6478.14, 1e+06] km"),
    (("constellation", "--outage-sats", "1,2,9"), "--outage-sats", "'1,2,9' is not three distinct"),
    (("psi", "--alpha", "-1"), "--alpha", "-1 is not in [0, inf)"),
]

CASES = [
    *(Case((*MC_1D, *extra), (option,)) for extra, option in DETECT_ENGINE),
    *(Case(tuple(args), (f"Invalid value for {option}: ", word)) for args, option, word in DETECT_CORE),
    *(
        Case((*args, *(() if "--out" in args else ("--out", f"{TMP}/out.csv"))), (option, text))
        for args, option, text in ENCODE
    ),
    *(
        Case(("encode", "correlations", f"{TMP}/x.csv"), (text,), files=(("x.csv", content),))
        for content, text in ENCODE_CSV
    ),
    *(Case(("jam-bound", *args, *OUT), (option,)) for args, option in JAM),
    *(
        Case(("jam-bound", *args), (), start=f"motionsig jam-bound {args[0]}: error: {m}")
        for args, m in JAM_CONFIG
    ),
    *(Case(("mac-roc", *args, *OUT), (needle,)) for args, needle in MAC),
    *(Case(("mac-roc", *args), (needle,)) for args, needle in MAC_REVIEW + MAC_CONFIG),
    *(Case(("maneuver", "--runs", "2", "--scans", "20", *args, *OUT), (needle,)) for args, needle in MAN),
    *(
        Case(
            ("maneuver", "--input", f"{TMP}/bad.csv", *OUT),
            (needle,),
            files=(("bad.csv", "# sigma: 100\nscan,z_x,z_y\n" + body),),
        )
        for body, needle in MAN_REC
    ),
    *(
        Case(("maneuver", "--input", f"{TMP}/r.csv", *args), (needle,), files=(("r.csv", meta + MAN_BODY),))
        for args, meta, needle in MAN_META
    ),
    *(Case(("simulate", *args), (f"Invalid value for {option}:", text)) for args, option, text in SIM),
    *(Case(("simulate", *args), (option, text)) for args, option, text in SIMDET_SIM),
    *(Case(("simulate", "--example", "2d", "--duration", "1", *args), (hint,)) for args, hint in SIM_2D),
    Case(("simulate", "--R-range", "1e-3", "--duration", "1"), ("--example 2d",)),
    *(Case(("slrt", *args), (needle,), start="motionsig slrt: error: ", plain=True) for args, needle in SLRT),
    *(Case(("slrt", *args), (message,)) for args, message in SLRT_CORE),
    *(Case(("track-sat", *args), (needle,)) for args, needle in TRACK),
    *(
        Case(
            ("track-sat", *args), (option, detail), start=f"motionsig track-sat {args[0]}: error:", plain=True
        )
        for args, option, detail in TRACK_CONFIG
    ),
]


@pytest.mark.parametrize("case", CASES, ids=lambda c: " ".join(c.args).replace(TMP, "TMP"))
def test_bad_input_is_one_line_exit_2_naming_the_option(capsys, tmp_path, monkeypatch, case):
    monkeypatch.chdir(tmp_path)  # a relative path a case names lands in tmp_path
    for name, text in case.files:
        (tmp_path / name).write_text(text)
    err = one_line_error(capsys, *(a.replace(TMP, str(tmp_path)) for a in case.args))
    assert err.startswith(case.start), err
    assert all(n.replace(TMP, str(tmp_path)) in err for n in case.needles), err
    assert not case.plain or "Input should" not in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(name for name, _ in case.files)  # no output
