"""``motionsig encode``: m-sequences, preferred pairs, Gold families, GPS C/A, Table I, correlations,
signature waveforms (seed 000 §II.A, eqs 1–3, Table I).

Every code-producing command writes the same long table ``code,chip,value`` (plus descriptive
columns), so any of them can be piped into ``motionsig encode correlations -``.
"""

from __future__ import annotations

import math
from enum import StrEnum
from typing import Annotated

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
    int_list,
    note,
    progress,
    save_figure,
)
from motionsig_cli.cli.io import InputError, Table, emit, make_meta, read_table
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals import gf2, gold, gps, modes
from motionsig_cli.signals.correlation import (
    correlation_rows,
    degree_of_period,
    gold_bound,
    offpeak_counts,
    periodic_correlation,
    summarize,
    to_bipolar,
)
from motionsig_cli.signals.lfsr import MAX_SEQUENCE_DEGREE, default_state, m_sequence, parse_state
from motionsig_cli.signals.signature import SignatureConfig, mode_signature

app = typer.Typer(
    help="Gold codes, m-sequences, GPS C/A codes, Table I mode codes, correlations and mode signatures.",
    no_args_is_help=True,
)


class Chips(StrEnum):
    """How code chips are written."""

    bits = "bits"
    bipolar = "bipolar"


class Table1View(StrEnum):
    """What ``encode table1`` shows."""

    codes = "codes"
    summary = "summary"
    errata = "errata"


class CorrView(StrEnum):
    """What ``encode correlations`` shows."""

    summary = "summary"
    values = "values"
    full = "full"


class Zdot(StrEnum):
    """Derivative of the signature."""

    analytic = "analytic"
    finite_difference = "finite-difference"


ChipsOpt = Annotated[
    Chips, typer.Option("--chips", help="bits (0/1) or bipolar (bit 0 -> -1, bit 1 -> +1, seed's BPSK).")
]


def _poly(option: str, text: str) -> int:
    poly = checked(option, gf2.parse_polynomial, text)
    if gf2.degree(poly) > MAX_SEQUENCE_DEGREE:
        raise typer.BadParameter(
            f"degree {gf2.degree(poly)} > {MAX_SEQUENCE_DEGREE}: sequences of period 2^n-1 are tabulated up to "
            f"n = {MAX_SEQUENCE_DEGREE}",
            param_hint=option,
        )
    return checked(option, gf2.require_primitive, poly)


def _state(option: str, text: str | None, n: int) -> tuple[int, ...]:
    return default_state(n) if text is None else checked(option, parse_state, text, n)


def _chip_values(bits: np.ndarray, chips: Chips) -> np.ndarray:
    return to_bipolar(bits) if chips is Chips.bipolar else np.asarray(bits, dtype=np.uint8)


def _codes_table(
    labels: list[str],
    codes: np.ndarray,
    chips: Chips,
    meta: dict,
    extra: dict[str, list] | None = None,
) -> Table:
    """Long ``code,chip,value`` table (one row per chip) with optional per-code columns."""
    extra = extra or {}
    cols = ("code", *extra.keys(), "chip", "value")
    rows = []
    for i, (label, bits) in enumerate(zip(labels, codes, strict=True)):
        vals = _chip_values(bits, chips)
        per_code = tuple(v[i] for v in extra.values())
        rows.extend((label, *per_code, j, int(v)) for j, v in enumerate(vals))
    return Table(columns=cols, rows=rows, meta=meta)


@app.command("mseq")
def mseq(
    poly: Annotated[
        str, typer.Option("--poly", help="Primitive polynomial: octal (45) or exponents (x^5+x^2+1).")
    ] = "45",
    init: Annotated[
        str | None, typer.Option("--init", help="Initial state [s_{n-1} ... s_0] (MATLAB order), e.g. 00001.")
    ] = None,
    shift: Annotated[int, typer.Option("--shift", help="Cyclic advance of the output.")] = 0,
    chips: ChipsOpt = Chips.bits,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """One period of the m-sequence of a primitive polynomial (s_{t+n} = sum c_i s_{t+i} mod 2).

    \b
    Example:
      motionsig encode mseq --poly 'x^5+x^2+1' --init 00001
      # -> 1000010010110011111000110111010 (MATLAB comm.PNSequence)
    """
    check_outputs(out)
    p = _poly("--poly", poly)
    n = gf2.degree(p)
    state = _state("--init", init, n)
    bits = m_sequence(p, state, shift)
    meta = make_meta(
        "encode mseq",
        poly_octal=gf2.to_octal(p),
        poly=gf2.to_exponents(p),
        degree=n,
        init="".join(map(str, state)),
        shift=shift,
        chips=chips.value,
        convention="MATLAB comm.PNSequence",
    )
    emit(_codes_table([f"m_{gf2.to_octal(p)}"], bits[None, :], chips, meta), fmt.value, out)


@app.command("check-pair")
def check_pair(
    poly1: Annotated[str, typer.Option("--poly1", help="First primitive polynomial (octal or exponents).")],
    poly2: Annotated[str, typer.Option("--poly2", help="Second primitive polynomial of the same degree.")],
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Test a preferred pair: is the periodic cross-correlation {-t(n), -1, t(n)-2}?

    \b
    Example:
      motionsig encode check-pair --poly1 45 --poly2 75    # preferred: -9, -1, 7
      motionsig encode check-pair --poly1 45 --poly2 51    # reciprocal pair: 6 values
    """
    check_outputs(out)
    p1, p2 = _poly("--poly1", poly1), _poly("--poly2", poly2)
    res = checked("--poly2", gold.check_pair, p1, p2)
    table = Table(
        columns=("poly1", "poly2", "degree", "values", "expected", "preferred"),
        rows=[
            (
                gf2.to_octal(p1),
                gf2.to_octal(p2),
                res.degree,
                " ".join(map(str, res.values)),
                " ".join(map(str, res.expected))
                if res.expected
                else "none (no preferred pairs for this degree)",
                res.preferred,
            )
        ],
        meta=make_meta("encode check-pair", poly1=gf2.to_exponents(p1), poly2=gf2.to_exponents(p2)),
    )
    emit(table, fmt.value, out)
    note(
        f"({gf2.to_octal(p1)}, {gf2.to_octal(p2)}): {'preferred' if res.preferred else 'NOT preferred'}",
        quiet,
    )


def _degrees(text: str) -> list[int]:
    """'5', '3-11' or '5,7,9' → degrees; multiples of 4 inside a range are skipped, named ones rejected."""
    named = {int(p) for p in text.split(",") if p.strip().isascii() and p.strip().isdigit()}
    out = [n for n in int_list(text, what="degree", max_count=64) if n % 4 or n in named]
    if not out:
        raise ValueError(f"no degree in {text!r} has preferred pairs (n >= 3, n mod 4 != 0)")
    for n in out:
        gold.require_gold_degree(n)
        if n > 13:
            raise ValueError(f"degree {n} > 13: the exhaustive pair search is limited to n <= 13")
    return out


@app.command("pairs")
def pairs(
    degree: Annotated[str, typer.Option("--degree", help="Degree, range (3-11) or list (5,7).")] = "3-11",
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """List every preferred pair of the given degrees (exhaustive FFT test over primitive polynomials).

    \b
    Example:
      motionsig encode pairs --degree 5          # 12 pairs, 45/75 among them
      motionsig encode pairs --degree 3-11 -o pairs.csv
    """
    check_outputs(out)
    degrees = checked("--degree", _degrees, degree)
    rows = []
    with progress(quiet) as bar:
        task = bar.add_task("preferred pairs", total=len(degrees))
        for n in degrees:
            for a, b in gold.preferred_pairs(n):
                rows.append((n, gf2.to_octal(a), gf2.to_octal(b), gf2.to_exponents(a), gf2.to_exponents(b)))
            bar.advance(task)
    table = Table(
        columns=("degree", "poly1_octal", "poly2_octal", "poly1", "poly2"),
        rows=rows,
        meta=make_meta(
            "encode pairs", degrees=degrees, criterion="cross-correlation values == {-t(n), -1, t(n)-2}"
        ),
    )
    emit(table, fmt.value, out)
    note(f"{len(rows)} preferred pairs over degrees {degrees}", quiet)


@app.command("gold")
def gold_cmd(
    poly1: Annotated[
        str, typer.Option("--poly1", help="First polynomial of the preferred pair (octal or exponents).")
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
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Gold codes of a preferred pair (MATLAB comm.GoldSequence conventions: Index, Shift, init states).

    \b
    Example:
      motionsig encode gold --poly1 45 --poly2 75 --index 9 --shift 8   # Table I mode 1
      motionsig encode gold --poly1 45 --poly2 75 --all | motionsig encode correlations -
    """
    check_outputs(out)
    if all_members and (index is not None or shift is not None):
        raise typer.BadParameter("--all lists every member; drop --index/--shift", param_hint="--all")
    index = 0 if index is None else index
    shift = 0 if shift is None else shift
    p1, p2 = _poly("--poly1", poly1), _poly("--poly2", poly2)
    n = gf2.degree(p1)
    if gf2.degree(p2) != n:
        raise typer.BadParameter(
            f"degree {gf2.degree(p2)} differs from --poly1's degree {n}", param_hint="--poly2"
        )
    if not unchecked:
        checked("--poly1/--poly2", gold.require_preferred, p1, p2)
    s1, s2 = _state("--init1", init1, n), _state("--init2", init2, n)
    meta = make_meta(
        "encode gold",
        poly1=gf2.to_octal(p1),
        poly2=gf2.to_octal(p2),
        degree=n,
        init1="".join(map(str, s1)),
        init2="".join(map(str, s2)),
        index="all" if all_members else index,
        shift=0 if all_members else shift,
        chips=chips.value,
        preferred_checked=not unchecked,
        convention="MATLAB comm.GoldSequence",
    )
    if all_members:
        idx, codes = gold.gold_family(p1, p2, s1, s2) if not unchecked else _unchecked_family(p1, p2, s1, s2)
        labels = [f"gold_k{k}" for k in idx]
        table = _codes_table(labels, codes, chips, meta, {"index": list(idx), "shift": [0] * len(idx)})
    else:
        period = (1 << n) - 1
        if not -2 <= index <= period - 1:
            raise typer.BadParameter(f"must be in -2..{period - 1} for degree {n}", param_hint="--index")
        bits = gold.gold_code(p1, p2, index, shift, s1, s2, verify=False)
        table = _codes_table(
            [f"gold_k{index}_a{shift}"], bits[None, :], chips, meta, {"index": [index], "shift": [shift]}
        )
    emit(table, fmt.value, out)


def _unchecked_family(p1: int, p2: int, s1: tuple, s2: tuple) -> tuple[np.ndarray, np.ndarray]:
    period = (1 << gf2.degree(p1)) - 1
    idx = np.arange(-2, period)
    return idx, np.stack([gold.gold_code(p1, p2, int(k), 0, s1, s2, verify=False) for k in idx])


def _prns(text: str) -> list[int]:
    out = int_list(text, what="PRN", max_count=32)
    bad = [p for p in out if not 1 <= p <= 32]
    if bad:
        raise ValueError(f"PRN must be in 1..32, got {bad[0]}")
    return out


@app.command("gps")
def gps_cmd(
    prn: Annotated[str, typer.Option("--prn", help="PRN, range or list: 1, 1-32, 1,5,7.")] = "1-32",
    summary: Annotated[
        bool, typer.Option("--summary", help="One row per PRN: taps, G2 delay, first 10 chips in octal.")
    ] = False,
    chips: ChipsOpt = Chips.bits,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """GPS L1 C/A codes (IS-GPS-200), 1023 chips: the degree-10 Gold-code reference.

    \b
    Example:
      motionsig encode gps --prn 1-10 --summary        # first-10-chip octals 1440, 1620, ...
      motionsig encode gps --prn 1-32 | motionsig encode correlations - --view values
    """
    check_outputs(out)
    prns = checked("--prn", _prns, prn)
    codes = gps.ca_codes(prns)
    taps = gps.phase_selectors()
    meta = make_meta(
        "encode gps",
        prn=prns,
        summary=summary,
        chips=chips.value,
        source="IS-GPS-200 Table 3-Ia phase selectors",
    )
    if summary:
        delays = gps.g2_delays()
        rows = [
            (p, f"{taps[p][0]}+{taps[p][1]}", delays[p], gps.first_chips_octal(c))
            for p, c in zip(prns, codes, strict=True)
        ]
        table = Table(columns=("prn", "g2_taps", "g2_delay_chips", "first10_octal"), rows=rows, meta=meta)
    else:
        table = _codes_table([f"PRN{p}" for p in prns], codes, chips, meta)
    emit(table, fmt.value, out)


@app.command("table1")
def table1(
    codes: Annotated[
        CodesVariant,
        typer.Option("--codes", help="corrected Gold codes (default) or the strings as printed."),
    ] = CodesVariant.corrected,
    view: Annotated[
        Table1View, typer.Option("--view", help="codes (long table), summary (one row per mode) or errata.")
    ] = Table1View.codes,
    chips: ChipsOpt = Chips.bits,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Table I of seed 000: the three 31-chip mode signatures, corrected or as printed.

    The corrected codes are the members of the 45/75 Gold family nearest the printed strings
    (mode 1 identical; mode 2 differs at chip 15; mode 3 has one chip dropped and one inserted).

    \b
    Example:
      motionsig encode table1 --view errata
      motionsig encode table1 --codes printed | motionsig encode correlations -
    """
    check_outputs(out)
    labels = [f"mode{m}" for m, _ in modes.modes()]
    printed, corrected = modes.printed_codes(), modes.corrected_codes()
    members = modes.corrected_members()
    meta = make_meta(
        "encode table1",
        codes=codes.value,
        view=view.value,
        chips=chips.value,
        pair="45/75",
        init1=modes.TABLE1_STATES[0],
        init2=modes.TABLE1_STATES[1],
        convention="MATLAB comm.GoldSequence",
        source="seed 000 Table I",
    )
    if view is Table1View.codes:
        chosen = corrected if codes is CodesVariant.corrected else printed
        extra = {"behavior": [b for _, b in modes.modes()]}
        table = _codes_table(labels, chosen, chips, meta, extra)
        if codes is CodesVariant.printed:
            note(
                "warning: printed Table I codes 2 and 3 are not Gold codes (mode 2 chip 15; mode 3 slip); "
                "see --view errata",
                quiet,
            )
    elif view is Table1View.summary:
        chosen = corrected if codes is CodesVariant.corrected else printed
        rows = []
        for (m, b), bits, (k, a) in zip(modes.modes(), chosen, members, strict=True):
            gold_member = codes is CodesVariant.corrected or np.array_equal(
                bits, modes.corrected_codes()[m - 1]
            )
            rows.append(
                (
                    m,
                    b,
                    modes.bit_string(bits),
                    int(bits.sum()),
                    k if gold_member else "",
                    a if gold_member else "",
                )
            )
        table = Table(
            columns=("mode", "behavior", "code", "ones", "family_index", "family_shift"), rows=rows, meta=meta
        )
    else:
        rows = []
        for (m, b), p, near, (k, a) in zip(
            modes.modes(), printed, modes.nearest_members(printed), members, strict=True
        ):
            rows.append(
                (
                    m,
                    b,
                    modes.bit_string(p),
                    modes.bit_string(near.code),
                    near.index,
                    near.shift,
                    near.edit_distance,
                    near.hamming,
                    "; ".join(modes.alignment(p, near.code)) or "identical",
                    (near.index, near.shift) == (k, a),
                )
            )
        table = Table(
            columns=(
                "mode",
                "behavior",
                "printed",
                "corrected",
                "family_index",
                "family_shift",
                "edit_distance",
                "hamming",
                "differences",
                "matches_stored",
            ),
            rows=rows,
            meta=meta,
        )
    emit(table, fmt.value, out)


def _read_codes(source: str) -> tuple[list[str], np.ndarray, dict]:
    """Codes from a long ``code,chip,value`` table; values 0/1 or ±1 (converted to ±1).

    Also returns the producer's provenance block (empty for a hand-written CSV).
    """
    t = read_table(source, required=("code", "chip", "value"))
    labels = t.column("code")
    chip = t.numeric("chip", integer=True)
    value = t.numeric("value", integer=True)
    order: dict[str, list[int]] = {}
    for i, lab in enumerate(labels):
        order.setdefault(lab, []).append(i)
    if not order:
        raise InputError(f"{t.source}: no codes (only a header)")
    vals = set(np.unique(value).tolist())
    if vals <= {0, 1}:
        bipolar = 2 * value - 1
    elif vals <= {-1, 1}:
        bipolar = value
    elif vals <= {-1, 0, 1}:
        first_kind = {0: "0/1", 1: None, -1: "-1/+1"}
        kind = next(first_kind[v] for v in value.tolist() if first_kind[v])
        bad = next(i for i, v in enumerate(value.tolist()) if v == (-1 if kind == "0/1" else 0))
        raise InputError(
            f"{t.source}:{t.lines[bad]}: column 'value': {value[bad]} mixes chip conventions "
            f"(earlier rows use {kind})"
        )
    else:
        bad = next(i for i, v in enumerate(value) if v not in (0, 1, -1))
        raise InputError(
            f"{t.source}:{t.lines[bad]}: column 'value': {value[bad]} is not a chip (0/1 or -1/+1)"
        )
    codes, lengths = [], set()
    for lab, rows in order.items():
        c = chip[rows]
        n = len(rows)
        if n < 2:
            raise InputError(f"{t.source}:{t.lines[rows[0]]}: code {lab!r} has {n} chip; need at least 2")
        if sorted(c.tolist()) != list(range(n)):
            raise InputError(
                f"{t.source}:{t.lines[rows[0]]}: code {lab!r}: chips must be 0..{n - 1}, each once"
            )
        code = np.empty(n, dtype=np.int64)
        code[c] = bipolar[rows]
        codes.append(code)
        lengths.add(n)
    if len(lengths) != 1:
        raise InputError(f"{t.source}: codes have different lengths {sorted(lengths)}")
    return list(order), np.stack(codes), t.meta


@app.command("correlations")
def correlations(
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
    plot: PlotOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Periodic auto- and cross-correlations of a set of codes, checked against the Gold bound t(n).

    \b
    Example:
      motionsig encode table1 | motionsig encode correlations -
      motionsig encode gold --all | motionsig encode correlations - --view values
    """
    check_outputs(out, plot)
    labels, codes, producer = _read_codes(source)
    n_chips = codes.shape[1]
    n = degree_of_period(n_chips)
    bound = gold_bound(n) if n and n >= 3 and n % 4 else None  # Gold families exist for these n only
    auto, cross = offpeak_counts(codes)  # one pass over all pairs; the views below reuse or stream
    all_vals = sorted(set(auto) | set(cross))
    max_off = max((abs(v) for v in all_vals), default=0)
    within = None if bound is None else max_off <= bound
    meta = make_meta(
        "encode correlations",
        source=source,
        view=view.value,
        codes=len(labels),
        length=n_chips,
        degree=n,
        gold_bound=bound,
        max_offpeak=max_off,
        within_gold_bound=within,
        offpeak_values=all_vals,
        definition="R_ab[l] = sum_t a_t b_(t+l mod N), bipolar chips; auto peak (a=b, l=0) excluded",
        input_meta=producer,
    )
    if view is CorrView.summary:
        pairs_ = summarize(codes)
        rows = [
            (
                labels[p.a],
                labels[p.b],
                "auto" if p.a == p.b else "cross",
                " ".join(map(str, p.values)),
                p.max_offpeak,
                bound if bound is not None else "",
                "" if bound is None else p.max_offpeak <= bound,
            )
            for p in pairs_
        ]
        table = Table(
            columns=("code_a", "code_b", "kind", "values", "max_offpeak", "gold_bound", "within_bound"),
            rows=rows,
            meta=meta,
        )
    elif view is CorrView.values:
        rows = [(v, auto.get(v, 0), cross.get(v, 0)) for v in all_vals]
        table = Table(columns=("value", "auto_count", "cross_count"), rows=rows, meta=meta)
    else:
        rows = [
            (labels[a], labels[a + j], lag, int(v))
            for a, block in correlation_rows(codes)
            for j, r in enumerate(block)
            for lag, v in enumerate(r)
        ]
        table = Table(columns=("code_a", "code_b", "lag", "value"), rows=rows, meta=meta)
    if plot is not None:
        from motionsig_cli.plotting import correlation_figure

        m = min(len(labels), 3)
        r = periodic_correlation(codes[:m])
        show = [(a, b) for a in range(m) for b in range(a, m)]
        fig = correlation_figure(
            np.arange(n_chips),
            np.stack([r[a, b] for a, b in show]),
            [f"{labels[a]}·{labels[b]}" for a, b in show],
            bound,
        )
        save_figure(fig, plot)
    emit(table, fmt.value, out)
    verdict = "" if bound is None else f"; Gold bound t({n}) = {bound}: {'within' if within else 'EXCEEDED'}"
    note(
        f"{len(labels)} codes of {n_chips} chips; off-peak values {all_vals}; max |R| = {max_off}{verdict}",
        quiet,
    )


def _theta(text: str, seed: int) -> float:
    if text.strip().lower() == "random":
        return float(trial_rng(seed, 0).uniform(0.0, 2 * math.pi))
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"expected radians or 'random', got {text!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"must be finite, got {text!r}")
    return value


@app.command("signature")
def signature(
    mode: Annotated[int, typer.Option("--mode", help="Table I mode (1, 2, 3).")] = 1,
    codes: Annotated[
        CodesVariant, typer.Option("--codes", help="Table I codes: corrected (default) or printed.")
    ] = CodesVariant.corrected,
    T: Annotated[float, typer.Option("--T", help="Sample interval [s] (assumption; seed silent).")] = 0.05,
    mrho: Annotated[
        int, typer.Option("--mrho", help="Samples per chip m_rho (assumption; seed silent).")
    ] = 20,
    fc: Annotated[float, typer.Option("--fc", help="Carrier frequency f_c [Hz].")] = 1.0,
    fd: Annotated[
        float, typer.Option("--fd", help="Frequency offset f_d of eq (3) [Hz] (0 in the seed).")
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
    plot: PlotOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Sampled mode signature z_k = p_k[tau] cos(2 pi (f_c + f_d) t_k + theta), replicas and derivatives (eqs 1-3).

    \b
    Example:
      motionsig encode signature --mode 1 --theta 0.5 --plot sig.png -o sig.csv
      motionsig encode signature --mode 2 --tau 40 --theta random --seed 7 | head
    """
    check_outputs(out, plot)
    if mode not in (1, 2, 3):
        raise typer.BadParameter(f"Table I has modes 1, 2, 3; got {mode}", param_hint="--mode")
    th = checked("--theta", _theta, theta, seed)
    cfg_opts = {
        "T": ("--T", T),
        "m_rho": ("--mrho", mrho),
        "f_c": ("--fc", fc),
        "f_d": ("--fd", fd),
        "tau": ("--tau", tau),
    }
    for field_name, (opt, value) in cfg_opts.items():  # validate each option on its own, to name it
        checked(opt, SignatureConfig, **{field_name: value})
    cfg = SignatureConfig(T=T, m_rho=mrho, f_c=fc, theta=th, tau=tau, f_d=fd)
    if length is not None and length < 1:
        raise typer.BadParameter(f"must be a positive number of samples, got {length}", param_hint="--length")
    bits = modes.table1_codes(codes.value)[mode - 1]
    sig = checked("--length/--mrho/--T/--fc/--fd", mode_signature, to_bipolar(bits), cfg, length, zdot.value)
    meta = make_meta(
        "encode signature",
        mode=mode,
        codes=codes.value,
        T=T,
        m_rho=mrho,
        f_c=fc,
        f_d=fd,
        theta=th,
        theta_option=theta,
        tau=tau,
        length=int(sig.k.size),
        zdot=zdot.value,
        seed=seed,
        assumptions="T=0.05 s and m_rho=20 are spec defaults (seed 000 silent)",
        equations="seed 000 eqs (1)-(3)",
    )
    cols = ("k", "t", "chip", "p", "z", "z_cos", "z_sin", "zdot", "zdot_cos", "zdot_sin")
    arrays = [
        sig.k,
        sig.t,
        sig.chip,
        sig.p,
        sig.z,
        sig.z_cos,
        sig.z_sin,
        sig.zdot,
        sig.zdot_cos,
        sig.zdot_sin,
    ]
    rows = [
        (int(k), float(t), int(c), int(p), float(a), float(b), float(c2), float(d), float(e), float(f))
        for k, t, c, p, a, b, c2, d, e, f in zip(*arrays, strict=True)
    ]
    if plot is not None:
        from motionsig_cli.plotting import signature_figure

        title = f"Mode {mode} signature ({codes.value}), τ = {tau} samples, θ = {th:.3f} rad"
        save_figure(signature_figure(sig, title=title, theta=th, f_c=fc + fd), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
