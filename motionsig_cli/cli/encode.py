"""``motionsig encode``: m-sequences, preferred pairs, Gold families, GPS C/A, Table I, correlations,
signature waveforms (§II.A, eqs 1–3 and Table I of the mode-signature paper, 47th IEEE CDC, Cancún, 2008), and the EBPSK waveform, impacting filter and BER of Yao, Teng & Wu's
joint radar–communication front end (``encode ebpsk``; :mod:`motionsig_cli.maneuver.ebpsk_link`).

Every code-producing command writes the same long table ``code,chip,value`` (plus descriptive
columns), so any of them can be piped into ``motionsig encode correlations -``. The tables are built by
:mod:`motionsig_cli.signals.code_sets`, imported when a command runs (NumPy, no SciPy).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import (
    DEFAULT_SEED_VALUE,
    CodesVariant,
    Output,
    Parallel,
    SeedOpt,
    choices,
    command,
)
from motionsig_cli.cli.option_groups import given, options

if TYPE_CHECKING:
    from motionsig_cli.signals.ebpsk import EBPSKConfig

app = typer.Typer(
    help="Gold codes, m-sequences, GPS C/A codes, Table I mode codes, correlations and mode signatures.",
    no_args_is_help=True,
)


Chips = choices("Chips", "How code chips are written.", "bits", "bipolar")
Table1View = choices("Table1View", "What ``encode table1`` shows.", "codes", "summary", "errata")
CorrView = choices("CorrView", "What ``encode correlations`` shows.", "summary", "values", "full")
Zdot = choices("Zdot", "Derivative of the signature.", "analytic", "finite-difference")


ChipsOpt = Annotated[
    Chips,
    typer.Option("--chips", help="bits (0/1) or bipolar (BPSK: bit 0 -> -1, bit 1 -> +1)."),
]
POLY_HELP = "octal (45) or exponents (x^5+x^2+1)"


@app.command("mseq")
@command(plot=False)
def mseq(
    output: Output,
    poly: Annotated[str, typer.Option("--poly", help=f"Primitive polynomial: {POLY_HELP}.")] = "45",
    init: Annotated[
        str | None, typer.Option("--init", help="Initial state [s_{n-1} ... s_0] (MATLAB order), e.g. 00001.")
    ] = None,
    shift: Annotated[int, typer.Option("--shift", help="Cyclic advance of the output.")] = 0,
    chips: ChipsOpt = Chips.bits,
) -> None:
    """One period of the m-sequence of a primitive polynomial (s_{t+n} = sum c_i s_{t+i} mod 2).

    \b
    Example:
      motionsig encode mseq --poly 'x^5+x^2+1' --init 00001
      # -> 1000010010110011111000110111010 (MATLAB comm.PNSequence)
    """
    output.check()
    from motionsig_cli.signals.code_sets import mseq_table
    from motionsig_cli.signals.lfsr import MSequenceConfig

    output.emit(mseq_table(MSequenceConfig(poly, init, shift), chips.value))


@app.command("check-pair")
@command(plot=False)
def check_pair(
    output: Output,
    poly1: Annotated[str, typer.Option("--poly1", help=f"First primitive polynomial: {POLY_HELP}.")],
    poly2: Annotated[str, typer.Option("--poly2", help="Second primitive polynomial of the same degree.")],
) -> None:
    """Test a preferred pair: is the periodic cross-correlation {-t(n), -1, t(n)-2}?

    \b
    Example:
      motionsig encode check-pair --poly1 45 --poly2 75    # preferred: -9, -1, 7
      motionsig encode check-pair --poly1 45 --poly2 51    # reciprocal pair: 6 values
    """
    output.check()
    from motionsig_cli.signals.code_sets import pair_check_table
    from motionsig_cli.signals.gold import GoldConfig

    table, verdict = pair_check_table(GoldConfig(poly1, poly2, preferred=False))
    output.emit(table)
    output.note(verdict)


def _degrees(text: str) -> list[int]:
    """'5', '3-11' or '5,7,9' → degrees; multiples of 4 inside a range are skipped, named ones kept (and
    rejected by the core)."""
    named = {int(p) for p in text.split(",") if p.strip().isascii() and p.strip().isdigit()}
    out = [n for n in common.int_list(text, what="degree", max_count=64) if n % 4 or n in named]
    if not out:
        raise ValueError(f"no degree in {text!r} has preferred pairs (n >= 3, n mod 4 != 0)")
    return out


@app.command("pairs")
@command(plot=False)
def pairs(
    output: Output,
    degree: Annotated[str, typer.Option("--degree", help="Degree, range (3-11) or list (5,7).")] = "3-11",
) -> None:
    """List every preferred pair of the given degrees (exhaustive FFT test over primitive polynomials).

    \b
    Example:
      motionsig encode pairs --degree 5          # 12 pairs, 45/75 among them
      motionsig encode pairs --degree 3-11 -o pairs.csv
    """
    output.check()
    degrees = common.checked("--degree", _degrees, degree)
    from motionsig_cli.signals.code_sets import pairs_table

    with common.progress_bar("preferred pairs", len(degrees), output.quiet) as advance:
        table, summary = pairs_table(degrees, advance)
    output.emit(table)
    output.note(summary)


@app.command("gold")
@command(plot=False)
def gold_cmd(
    output: Output,
    poly1: Annotated[
        str, typer.Option("--poly1", help=f"First polynomial of the preferred pair: {POLY_HELP}.")
    ] = "45",
    poly2: Annotated[str, typer.Option("--poly2", help="Second polynomial of the preferred pair.")] = "75",
    init1: Annotated[
        str | None, typer.Option("--init1", help="Initial state of register 1 (MATLAB order).")
    ] = None,
    init2: Annotated[
        str | None, typer.Option("--init2", help="Initial state of register 2 (MATLAB order).")
    ] = None,
    index: Annotated[
        int | None,
        typer.Option("--index", help="Member: -2 -> u, -1 -> v, k >= 0 -> u xor T^k v (default 0)."),
    ] = None,
    shift: Annotated[
        int | None, typer.Option("--shift", help="Start offset a of the member (default 0).")
    ] = None,
    all_members: Annotated[
        bool, typer.Option("--all", help="All 2^n+1 members (not with --index/--shift).")
    ] = False,
    unchecked: Annotated[
        bool,
        typer.Option(
            "--unchecked", help="Allow a non-preferred pair (as MATLAB does); result is not a Gold code."
        ),
    ] = False,
    chips: ChipsOpt = Chips.bits,
) -> None:
    """Gold codes of a preferred pair (MATLAB comm.GoldSequence conventions: Index, Shift, init states).

    \b
    Example:
      motionsig encode gold --poly1 45 --poly2 75 --index 9 --shift 8   # Table I mode 1
      motionsig encode gold --poly1 45 --poly2 75 --all | motionsig encode correlations -
    """
    output.check()
    if all_members and (index is not None or shift is not None):
        raise typer.BadParameter("--all lists every member; drop --index/--shift", param_hint="--all")
    from motionsig_cli.signals.code_sets import gold_table
    from motionsig_cli.signals.gold import GoldConfig

    config = GoldConfig(poly1, poly2, init1, init2, preferred=not unchecked)
    members = None if all_members else (index or 0, shift or 0)
    output.emit(gold_table(config, members, chips.value))


@app.command("gps")
@command(plot=False)
def gps_cmd(
    output: Output,
    prn: Annotated[str, typer.Option("--prn", help="PRN, range or list: 1, 1-32, 1,5,7.")] = "1-32",
    summary: Annotated[
        bool, typer.Option("--summary", help="One row per PRN: taps, G2 delay, first 10 chips in octal.")
    ] = False,
    chips: ChipsOpt = Chips.bits,
) -> None:
    """GPS L1 C/A codes (IS-GPS-200), 1023 chips: the degree-10 Gold-code reference.

    \b
    Example:
      motionsig encode gps --prn 1-10 --summary        # first-10-chip octals 1440, 1620, ...
      motionsig encode gps --prn 1-32 | motionsig encode correlations - --view values
    """
    output.check()
    prns = common.checked("--prn", common.int_list, prn, what="PRN", max_count=32)
    from motionsig_cli.signals.code_sets import gps_table

    output.emit(gps_table(prns, summary, chips.value))


@app.command("table1")
@command(plot=False)
def table1(
    output: Output,
    codes: Annotated[
        CodesVariant,
        typer.Option("--codes", help="corrected Gold codes (default) or the strings as printed."),
    ] = CodesVariant.corrected,
    view: Annotated[
        Table1View, typer.Option("--view", help="codes (long table), summary (one row per mode) or errata.")
    ] = Table1View.codes,
    chips: ChipsOpt = Chips.bits,
) -> None:
    """Table I of the mode-signature paper: the three 31-chip mode signatures, corrected or as printed.

    The paper is the mode-signature paper (47th IEEE CDC, Cancún, 2008). The corrected codes are
    the members of the 45/75 Gold family nearest the printed strings (mode 1 identical; mode 2 differs at
    chip 15; mode 3 has one chip dropped and one inserted).

    \b
    Example:
      motionsig encode table1 --view errata
      motionsig encode table1 --codes printed | motionsig encode correlations -
    """
    output.check()
    from motionsig_cli.signals.code_sets import table1_table

    table, warning = table1_table(codes.value, view.value, chips.value)
    output.emit(table)
    if warning:
        output.note(warning)


@app.command("correlations")
@command()
def correlations(
    output: Output,
    source: Annotated[
        str,
        typer.Argument(help="CSV with columns code,chip,value (from any encode command), or - for stdin."),
    ],
    view: Annotated[
        CorrView,
        typer.Option(
            "--view", help="summary (per pair), values (distinct values with counts) or full (every lag)."
        ),
    ] = CorrView.summary,
) -> None:
    """Periodic auto- and cross-correlations of a set of codes, checked against the Gold bound t(n).

    \b
    Example:
      motionsig encode table1 | motionsig encode correlations -
      motionsig encode gold --all | motionsig encode correlations - --view values
    """
    output.check()
    from motionsig_cli.signals.code_sets import correlation_curves, correlations_table, load_codes

    codes = load_codes(source)
    table, summary = correlations_table(codes, source, view.value)
    if output.plot is not None:
        from motionsig_cli.plotting import correlation_figure

        output.figure(correlation_figure(*correlation_curves(codes)))
    output.emit(table)
    output.note(summary)


@app.command("signature")
@command(options={"m_rho": "--mrho", "f_c": "--fc", "f_d": "--fd"})
def signature(
    output: Output,
    mode: Annotated[int, typer.Option("--mode", help="Table I mode (1, 2, 3).")] = 1,
    codes: Annotated[
        CodesVariant, typer.Option("--codes", help="Table I codes: corrected (default) or printed.")
    ] = CodesVariant.corrected,
    T: Annotated[float, typer.Option("--T", help="Sample interval [s] (assumed).")] = 0.05,
    mrho: Annotated[int, typer.Option("--mrho", help="Samples per chip m_rho (assumed).")] = 20,
    fc: Annotated[float, typer.Option("--fc", help="Carrier frequency f_c [Hz].")] = 1.0,
    fd: Annotated[
        float, typer.Option("--fd", help="Frequency offset f_d of eq (3) [Hz] (0 in the paper).")
    ] = 0.0,
    theta: Annotated[
        str, typer.Option("--theta", help="Carrier phase [rad], or 'random' (uniform, from --seed).")
    ] = "0",
    tau: Annotated[int, typer.Option("--tau", help="Code phase in samples.")] = 0,
    length: Annotated[
        int | None, typer.Option("--length", help="Samples; default one code period n_rho*m_rho.")
    ] = None,
    zdot: Annotated[
        Zdot, typer.Option("--zdot", help="Derivative: analytic (chip edges ignored) or finite-difference.")
    ] = Zdot.analytic,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
) -> None:
    """Sampled mode signature z_k = p_k[tau] cos(2 pi (f_c + f_d) t_k + theta), replicas and derivatives (eqs 1-3).

    Eqs (1)-(3) of the mode-signature paper (47th IEEE CDC, Cancún, 2008);
    the sample interval T and the samples per chip m_rho are assumed (the paper does not state them).

    \b
    Example:
      motionsig encode signature --mode 1 --theta 0.5 --plot sig.png -o sig.csv
      motionsig encode signature --mode 2 --tau 40 --theta random --seed 7 | head
    """
    output.check()
    from motionsig_cli.signals.code_sets import resolve_theta, signature_table
    from motionsig_cli.signals.signature import SignatureConfig

    th = resolve_theta(theta, seed)
    config = SignatureConfig(T=T, m_rho=mrho, f_c=fc, theta=th, tau=tau, f_d=fd)
    table, sig = signature_table(
        mode, codes.value, config, length=length, zdot=zdot.value, seed=seed, theta_option=theta
    )
    if output.plot is not None:
        from motionsig_cli.plotting import signature_figure

        title = f"Mode {mode} signature ({codes.value}), τ = {tau} samples, θ = {th:.3f} rad"
        output.figure(signature_figure(sig, title=title, theta=th, f_c=fc + fd))
    output.emit(table)


Statistic = choices("Statistic", "Statistic of the EBPSK impacting-filter demodulator.", "peak", "energy")
ReceiverName = choices(
    "ReceiverName", "The EBPSK receiver.", "differential", "impacting", "impacting-assumed", "matched"
)
EBPSK_OPTIONS = {
    "theta": "--theta",
    "ebn0_db": "--ebn0",
    "codes": "--code",
    "f_if": "--f-if",
    "f_carrier": "--f-carrier",
}
MAX_EBPSK_TABLE_SAMPLES = 5_000_000  # rows of one waveform table


def _ebpsk_bits(bits: str | None, code: str | None) -> tuple[object, str]:
    """The bits of ``--bits`` (a string of 0 and 1; spaces, commas and underscores ignored) or of the chips
    of ``--code`` (every code of the set, in order; chip +1 is bit 1), and their description."""
    if bits is not None and code is not None:
        raise typer.BadParameter("give --bits or --code, not both", param_hint="--bits")
    if code is not None:
        from motionsig_cli.signals.code_spec import parse_codes

        codes = parse_codes(code)
        return (codes.chips > 0).astype("int8").reshape(-1), f"code {codes.spec} ({', '.join(codes.names)})"
    text = "0110" if bits is None else bits
    cleaned = [c for c in text if c not in " ,_"]
    bad = [c for c in cleaned if c not in "01"]
    if bad:
        raise typer.BadParameter(
            f"{text!r} holds {bad[0]!r}: bits are 0 or 1, e.g. 0110", param_hint="--bits"
        )
    if not cleaned:
        raise typer.BadParameter(f"{text!r} holds no bit: give at least one, e.g. 0110", param_hint="--bits")
    return [int(c) for c in cleaned], "".join(cleaned)


@dataclass(frozen=True)
class Waveform:
    """The EBPSK waveform and impacting filter (Table I of Yao, Teng & Wu; the filter's placement assumed)."""

    N: Annotated[int, typer.Option("--N", help="Carrier cycles per symbol (Table I: 7).")] = 7
    K: Annotated[
        int, typer.Option("--K", help="Phase-changed cycles of a bit 1, 1 <= K < N (Table I: 2).")
    ] = 2
    theta: Annotated[float, typer.Option("--theta", help="Modulation angle [rad], in (0, 2 pi).")] = math.pi
    f_if: Annotated[float, typer.Option("--f-if", help="Intermediate frequency [Hz] (Table I: 100 MHz).")] = (
        100e6
    )
    fs: Annotated[float, typer.Option("--fs", help="Sampling frequency [Hz], > 2 f_if (Table I: 1 GHz).")] = (
        1e9
    )
    f_carrier: Annotated[
        float, typer.Option("--f-carrier", help="RF carrier [Hz], metadata only (Table I: 10 GHz).")
    ] = 10e9
    pole_radius: Annotated[
        float, typer.Option("--pole-radius", help="Impacting filter: pole radius in (0, 1) (assumed).")
    ] = 0.93
    pole_offset: Annotated[
        float, typer.Option("--pole-offset", help="Impacting filter: poles at f_if(1 +- offset) (assumed).")
    ] = 0.08
    zero_offset: Annotated[
        float, typer.Option("--zero-offset", help="Impacting filter: zeros at f_if(1 + offset) (assumed 0).")
    ] = 0.0

    def config(self) -> EBPSKConfig:
        """The waveform's configuration (which checks every value)."""
        from motionsig_cli.signals.ebpsk import EBPSKConfig

        return EBPSKConfig(**dataclasses.asdict(self))


@dataclass(frozen=True)
class Ber:
    """The BER Monte Carlo of ``--ber`` (None: its defaults)."""

    receiver: Annotated[
        ReceiverName | None,
        typer.Option(
            "--receiver",
            help="With --ber: differential (noncoherent, default), impacting (designed filter), "
            "impacting-assumed (the earlier default's filter) or matched (coherent reference).",
        ),
    ] = None
    span: Annotated[
        int | None,
        typer.Option("--span", help="With --receiver differential: symbol tails in the phase reference (3)."),
    ] = None
    q: Annotated[
        float | None,
        typer.Option("--q", help="With --receiver impacting: resonator Q of the filter (default pi K)."),
    ] = None
    ebn0: Annotated[
        str | None, typer.Option("--ebn0", help="With --ber: Eb/N0 values [dB] (default 0,2,...,20).")
    ] = None
    trials: Annotated[int | None, typer.Option("--trials", help="With --ber: records per Eb/N0 (100).")] = (
        None
    )
    bits_per_trial: Annotated[
        int | None, typer.Option("--bits-per-trial", help="With --ber: data bits per record (1000).")
    ] = None
    statistic: Annotated[
        Statistic | None,
        typer.Option(
            "--statistic",
            help="With an impacting receiver: peak (max |y|, default) or energy in each symbol's window.",
        ),
    ] = None
    threshold: Annotated[
        float | None,
        typer.Option(
            "--threshold",
            help="With an impacting receiver: fixed threshold (default: minimum-error, calibrated).",
        ),
    ] = None

    def refuse(self) -> None:
        """Without --ber, these options are usage errors."""
        for name in given(self):
            raise typer.BadParameter("applies with --ber only", param_hint="--" + name.replace("_", "-"))


@app.command("ebpsk")
@command(parallel=True, options=EBPSK_OPTIONS)
@options(waveform=Waveform, ber_options=Ber)
def ebpsk_cmd(
    bits: Annotated[
        str | None, typer.Option("--bits", help="Bits to send, e.g. 0110 (default 0110; not with --ber).")
    ] = None,
    code: Annotated[
        str | None,
        typer.Option(
            "--code", help="Send the chips of a code set instead (gold:45,75:1, gps:1, corrected ...)."
        ),
    ] = None,
    waveform: Waveform = Waveform(),
    ber: Annotated[
        bool, typer.Option("--ber", help="BER vs Eb/N0 Monte Carlo of the amplitude demodulator instead.")
    ] = False,
    ber_options: Ber = Ber(),
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    *,
    output: Output,
    parallel: Parallel,
) -> None:
    """EBPSK waveform and impacting filter (Yao, Teng & Wu's JRC front end), or a receiver's BER with --ber.

    A symbol is N IF cycles; a bit 1 changes the phase of its first K cycles by theta. The impacting filter
    (a zero pair on the carrier, two pole pairs beside it: assumed placement) turns each phase jump into an
    impulse. The output table is sample, t, bit, symbol, x (IF waveform), y (filter output, from rest: the
    first symbol shows the carrier switching on). --ber gives BER vs Eb/N0 with binomial SE beside the
    coherent bound Q(sqrt((1-rho) Eb/N0)), which no receiver beats, and the receiver's closed form where it
    has one. The default receiver is differential: the phase of the first K cycles against the unmodulated
    rest of the symbol (and its neighbours', --span), no carrier phase needed; 0.1 dB from the bound at a
    BER of 1e-2 (0.4 dB with --span 1).

    \b
    Example:
      motionsig encode ebpsk --bits 0110100 --plot ebpsk.png -o ebpsk.csv
      motionsig encode ebpsk --code gold:45,75:1 | head
      motionsig encode ebpsk --ber --trials 50 --plot ber.png
      motionsig encode ebpsk --ber --receiver impacting --trials 50
    """
    output.check()
    cfg = waveform.config()
    if ber:
        if bits is not None or code is not None:
            raise typer.BadParameter(
                "--ber sends random bits: drop --bits/--code",
                param_hint="--bits" if bits is not None else "--code",
            )
        _ebpsk_ber(cfg, ber_options, seed, output, parallel)
        return
    ber_options.refuse()
    _ebpsk_waveform(cfg, bits, code, output)


def _ebpsk_waveform(cfg: EBPSKConfig, bits: str | None, code: str | None, output: Output) -> None:
    """The waveform table of ``--bits`` or ``--code`` and its figure."""
    sent, source = _ebpsk_bits(bits, code)
    from motionsig_cli.maneuver.ebpsk_link import waveform_table
    from motionsig_cli.signals.ebpsk import check_bits

    arr = check_bits(sent)
    if arr.size * cfg.samples_per_symbol > MAX_EBPSK_TABLE_SAMPLES:
        raise typer.BadParameter(
            f"{arr.size} bits of {cfg.samples_per_symbol} samples make more than {MAX_EBPSK_TABLE_SAMPLES} rows",
            param_hint="--code" if code is not None else "--bits",
        )
    table, x, y = waveform_table(cfg, arr, source)
    if output.plot is not None:
        import numpy as np

        from motionsig_cli.plotting import ebpsk_waveform_figure
        from motionsig_cli.signals.ebpsk import filter_response

        f, h = filter_response(cfg)
        t = np.arange(x.size) / cfg.fs
        title = f"EBPSK K = {cfg.K}, N = {cfg.N}, θ = {cfg.theta:.3g} rad, f_if = {cfg.f_if / 1e6:g} MHz"
        output.figure(ebpsk_waveform_figure(t, x, y, arr, cfg.symbol_duration, f, h, cfg.f_if, title=title))
    output.emit(table)
    output.note(
        f"{arr.size} bits, {x.size} samples; impact ratio (min bit-1 / max bit-0 peak) "
        f"{table.meta['impact_ratio']:.3g}"
    )


def _ebpsk_ber(cfg: EBPSKConfig, opts: Ber, seed: int, output: Output, parallel: Parallel) -> None:
    """``--ber``: BER vs Eb/N0 on the engine."""
    ebn0, trials, bits_per_trial, statistic = opts.ebn0, opts.trials, opts.bits_per_trial, opts.statistic
    from motionsig_cli.maneuver.ebpsk_link import DEFAULT_EBN0_DB, BerJob
    from motionsig_cli.signals.ebpsk import DEFAULT_SPAN, Receiver

    name = "differential" if opts.receiver is None else opts.receiver.value
    for option, value, applies in (
        ("--span", opts.span, name == "differential"),
        ("--q", opts.q, name == "impacting"),
        ("--statistic", statistic, name.startswith("impacting")),
        ("--threshold", opts.threshold, name.startswith("impacting")),
    ):
        if value is not None and not applies:
            raise typer.BadParameter(f"does not apply to --receiver {name}", param_hint=option)
    receiver = Receiver(
        name,
        span=DEFAULT_SPAN if opts.span is None else opts.span,
        statistic="peak" if statistic is None else statistic.value,
        q=opts.q,
    )

    values = (
        DEFAULT_EBN0_DB
        if ebn0 is None
        else tuple(common.checked("--ebn0", common.float_list, ebn0, what="Eb/N0"))
    )
    engine = parallel.engine()
    job = BerJob(
        cfg=cfg,
        ebn0_db=values,
        trials=100 if trials is None else trials,
        bits_per_trial=1000 if bits_per_trial is None else bits_per_trial,
        receiver=receiver,
        threshold=opts.threshold,
        seed=seed,
    )
    result = common.run_job(job, engine, "EBPSK BER", output.quiet)
    if output.plot is not None:
        import numpy as np

        from motionsig_cli.plotting import ebpsk_ber_figure

        title = f"EBPSK K = {job.cfg.K}, N = {job.cfg.N}: {result.bits} bits per point"
        curves = [(receiver.describe(), result.ber, result.se)]
        output.figure(ebpsk_ber_figure(np.array(result.ebn0_db), curves, result.bound, title=title))
    output.emit(result.table())
    output.note(result.summary())
