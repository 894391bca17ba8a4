"""The tables of ``motionsig encode``: m-sequences, preferred pairs, Gold families, GPS C/A codes, Table I of
the mode-signature paper (47th IEEE CDC, Cancún, 2008), periodic
correlations and sampled mode signatures (the paper's §II.A, eqs 1–3).

Every code-producing table is the long table ``code,chip,value`` (plus descriptive columns), so that any of
them can be read back by :func:`load_codes` and correlated by :func:`correlations_table`. Each function
returns a :class:`~motionsig_cli.tables.Table` with its provenance (and, where the command prints one, a
one-line summary); the parameters are checked by the configurations of :mod:`motionsig_cli.signals` or
here, with a :class:`~motionsig_cli.config.ConfigError` naming the field. Each function imports the
generators it needs, so that ``encode gps`` starts without loading Table I or the signature sampler.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of
from motionsig_cli.errors import InputError
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals import gf2, gps
from motionsig_cli.signals.correlation import (
    correlation_rows,
    degree_of_period,
    gold_bound,
    offpeak_counts,
    periodic_correlation,
    summarize,
    to_bipolar,
)
from motionsig_cli.tables import Table, make_meta, read_table

if TYPE_CHECKING:
    from motionsig_cli.signals.gold import GoldConfig
    from motionsig_cli.signals.lfsr import MSequenceConfig
    from motionsig_cli.signals.signature import Signature, SignatureConfig

CHIPS = ("bits", "bipolar")  # how chips are written: 0/1, or the paper's BPSK (bit 0 → −1, bit 1 → +1)
TABLE1_VIEWS = ("codes", "summary", "errata")
CORRELATION_VIEWS = ("summary", "values", "full")
ZDOT = ("analytic", "finite-difference")
MODE_PAPER = "the mode-signature paper (47th IEEE CDC, Cancún, 2008)"


def codes_table(
    labels: Sequence[str],
    codes: np.ndarray,
    chips: str,
    meta: dict[str, Any],
    extra: dict[str, list[Any]] | None = None,
) -> Table:
    """Long ``code,chip,value`` table (one row per chip) with optional per-code columns ``extra``;
    ``chips`` is ``"bits"`` (0/1) or ``"bipolar"`` (±1)."""
    one_of("chips", chips, CHIPS)
    extra = extra or {}
    rows = []
    for i, (label, bits) in enumerate(zip(labels, codes, strict=True)):
        vals = to_bipolar(bits) if chips == "bipolar" else np.asarray(bits, dtype=np.uint8)
        per_code = tuple(v[i] for v in extra.values())
        rows.extend((label, *per_code, j, int(v)) for j, v in enumerate(vals))
    return Table(columns=("code", *extra.keys(), "chip", "value"), rows=rows, meta=meta)


# ------------------------------------------------------------------ m-sequences, pairs, Gold families
def mseq_table(config: MSequenceConfig, chips: str = "bits") -> Table:
    """One period of an m-sequence (``encode mseq``)."""
    p = int(config.poly)
    meta = make_meta(
        "encode mseq",
        poly_octal=gf2.to_octal(p),
        poly=gf2.to_exponents(p),
        degree=config.degree,
        init="".join(map(str, config.init or ())),
        shift=config.shift,
        chips=chips,
        convention="MATLAB comm.PNSequence",
    )
    return codes_table([f"m_{gf2.to_octal(p)}"], config.sequence()[None, :], chips, meta)


def pair_check_table(config: GoldConfig) -> tuple[Table, str]:
    """The preferred-pair test of ``config``'s polynomials (``encode check-pair``) and its verdict."""
    from motionsig_cli.signals.gold import check_pair

    p1, p2 = int(config.poly1), int(config.poly2)
    res = check_pair(p1, p2)
    expected = (
        " ".join(map(str, res.expected)) if res.expected else "none (no preferred pairs for this degree)"
    )
    table = Table(
        columns=("poly1", "poly2", "degree", "values", "expected", "preferred"),
        rows=[
            (
                gf2.to_octal(p1),
                gf2.to_octal(p2),
                res.degree,
                " ".join(map(str, res.values)),
                expected,
                res.preferred,
            )
        ],
        meta=make_meta("encode check-pair", poly1=gf2.to_exponents(p1), poly2=gf2.to_exponents(p2)),
    )
    verdict = "preferred" if res.preferred else "NOT preferred"
    return table, f"({gf2.to_octal(p1)}, {gf2.to_octal(p2)}): {verdict}"


def pairs_table(degrees: Sequence[int], advance: Callable[[int], None] | None = None) -> tuple[Table, str]:
    """Every preferred pair of each degree (``encode pairs``), by exhaustive test; ``advance(1)`` after
    each degree. Each degree must have preferred pairs and be ≤ 13 (checked before any search)."""
    from motionsig_cli.signals.gold import preferred_pairs, require_search_degree

    degrees = list(degrees)
    for n in degrees:
        require_search_degree(integer("degree", n))
    rows = []
    for n in degrees:
        for a, b in preferred_pairs(n):
            rows.append((n, gf2.to_octal(a), gf2.to_octal(b), gf2.to_exponents(a), gf2.to_exponents(b)))
        if advance is not None:
            advance(1)
    table = Table(
        columns=("degree", "poly1_octal", "poly2_octal", "poly1", "poly2"),
        rows=rows,
        meta=make_meta(
            "encode pairs", degrees=degrees, criterion="cross-correlation values == {-t(n), -1, t(n)-2}"
        ),
    )
    return table, f"{len(rows)} preferred pairs over degrees {degrees}"


def gold_table(config: GoldConfig, members: tuple[int, int] | None = (0, 0), chips: str = "bits") -> Table:
    """Gold codes (``encode gold``): the member ``members = (index, shift)``, or the whole family
    (``members=None``)."""
    meta = make_meta(
        "encode gold",
        poly1=gf2.to_octal(int(config.poly1)),
        poly2=gf2.to_octal(int(config.poly2)),
        degree=config.degree,
        init1="".join(map(str, config.init1 or ())),
        init2="".join(map(str, config.init2 or ())),
        index="all" if members is None else members[0],
        shift=0 if members is None else members[1],
        chips=chips,
        preferred_checked=config.preferred,
        convention="MATLAB comm.GoldSequence",
    )
    if members is None:
        idx, codes = config.family()
        extra = {"index": list(idx), "shift": [0] * len(idx)}
        return codes_table([f"gold_k{k}" for k in idx], codes, chips, meta, extra)
    index, shift = members
    bits = config.member(index, shift)
    return codes_table(
        [f"gold_k{index}_a{shift}"], bits[None, :], chips, meta, {"index": [index], "shift": [shift]}
    )


def gps_table(prns: Sequence[int], summary: bool = False, chips: str = "bits") -> Table:
    """GPS L1 C/A codes (``encode gps``), or one summary row per PRN (taps, G2 delay, first 10 chips in
    octal)."""
    one_of("chips", chips, CHIPS)
    prns = list(prns)
    codes = gps.ca_codes(prns)
    meta = make_meta(
        "encode gps", prn=prns, summary=summary, chips=chips, source="IS-GPS-200 Table 3-Ia phase selectors"
    )
    if not summary:
        return codes_table([f"PRN{p}" for p in prns], codes, chips, meta)
    taps, delays = gps.phase_selectors(), gps.g2_delays()
    rows = [
        (p, f"{taps[p][0]}+{taps[p][1]}", delays[p], gps.first_chips_octal(c))
        for p, c in zip(prns, codes, strict=True)
    ]
    return Table(columns=("prn", "g2_taps", "g2_delay_chips", "first10_octal"), rows=rows, meta=meta)


# ---------------------------------------------------------------------------------------- Table I
PRINTED_WARNING = "warning: printed Table I codes 2 and 3 are not Gold codes (mode 2 chip 15; mode 3 slip); see --view errata"


def table1_table(codes: str = "corrected", view: str = "codes", chips: str = "bits") -> tuple[Table, str]:
    """Table I of the mode-signature paper (``encode table1``): ``view`` ``"codes"`` (long table),
    ``"summary"`` (one row per mode) or ``"errata"`` (printed vs corrected); the note is a warning for the
    printed codes (empty otherwise)."""
    from motionsig_cli.signals import modes

    one_of("codes", codes, modes.VARIANTS)
    one_of("view", view, TABLE1_VIEWS)
    one_of("chips", chips, CHIPS)
    meta = make_meta(
        "encode table1",
        codes=codes,
        view=view,
        chips=chips,
        pair="45/75",
        init1=modes.TABLE1_STATES[0],
        init2=modes.TABLE1_STATES[1],
        convention="MATLAB comm.GoldSequence",
        source=f"{MODE_PAPER}, Table I",
    )
    if view == "errata":
        return Table(columns=ERRATA_COLUMNS, rows=_errata_rows(), meta=meta), ""
    chosen = modes.table1_codes(codes)  # type: ignore[arg-type]
    if view == "codes":
        labels = [f"mode{m}" for m, _ in modes.modes()]
        table = codes_table(labels, chosen, chips, meta, {"behavior": [b for _, b in modes.modes()]})
        return table, PRINTED_WARNING if codes == "printed" else ""
    rows = []
    corrected = modes.corrected_codes()
    for (m, b), bits, (k, a) in zip(modes.modes(), chosen, modes.corrected_members(), strict=True):
        gold_member = codes == "corrected" or np.array_equal(bits, corrected[m - 1])
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
    columns = ("mode", "behavior", "code", "ones", "family_index", "family_shift")
    return Table(columns=columns, rows=rows, meta=meta), ""


ERRATA_COLUMNS = (
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
)


def _errata_rows() -> list[tuple[Any, ...]]:
    """Each printed code beside its nearest family member, re-derived by search, and the edits between."""
    from motionsig_cli.signals import modes

    printed = modes.printed_codes()
    nearest = modes.nearest_members(printed)
    return [
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
        for (m, b), p, near, (k, a) in zip(
            modes.modes(), printed, nearest, modes.corrected_members(), strict=True
        )
    ]


# ----------------------------------------------------------------------------------- correlations
@dataclass(frozen=True)
class CodeSet:
    """Codes read from a ``code,chip,value`` table: labels, ``(M, N)`` ±1 chips, the producer's
    provenance block (empty for a hand-written CSV)."""

    labels: list[str]
    codes: np.ndarray
    meta: dict[str, Any]


def load_codes(source: str) -> CodeSet:
    """Codes from a long ``code,chip,value`` table (a path, or ``-`` for stdin); values 0/1 or ±1 (converted
    to ±1). A bad table is an :class:`~motionsig_cli.errors.InputError` naming the file and line."""
    t = read_table(source, required=("code", "chip", "value"))
    labels = t.column("code")
    chip = t.numeric("chip", integer=True)
    value = t.numeric("value", integer=True)
    order: dict[str, list[int]] = {}
    for i, lab in enumerate(labels):
        order.setdefault(lab, []).append(i)
    if not order:
        raise InputError(f"{t.source}: no codes (only a header)")
    bipolar = _bipolar(t, value)
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
    return CodeSet(list(order), np.stack(codes), t.meta)


def _bipolar(t: Table, value: np.ndarray) -> np.ndarray:
    """The ``value`` column as ±1 chips: all 0/1 or all ±1, else an error at the first offending row."""
    vals = set(np.unique(value).tolist())
    if vals <= {0, 1}:
        return 2 * value - 1
    if vals <= {-1, 1}:
        return value
    if vals <= {-1, 0, 1}:
        first_kind = {0: "0/1", 1: None, -1: "-1/+1"}
        kind = next(first_kind[v] for v in value.tolist() if first_kind[v])
        bad = next(i for i, v in enumerate(value.tolist()) if v == (-1 if kind == "0/1" else 0))
        raise InputError(
            f"{t.source}:{t.lines[bad]}: column 'value': {value[bad]} mixes chip conventions "
            f"(earlier rows use {kind})"
        )
    bad = next(i for i, v in enumerate(value) if v not in (0, 1, -1))
    raise InputError(f"{t.source}:{t.lines[bad]}: column 'value': {value[bad]} is not a chip (0/1 or -1/+1)")


def gold_bound_of(n_chips: int) -> tuple[int | None, int | None]:
    """``(n, t(n))`` for codes of 2ⁿ − 1 chips; t(n) is None where no Gold family exists (n < 3, 4 | n)."""
    n = degree_of_period(n_chips)
    return n, (gold_bound(n) if n and n >= 3 and n % 4 else None)


def correlations_table(codes: CodeSet, source: str, view: str = "summary") -> tuple[Table, str]:
    """Periodic auto- and cross-correlations of a set of codes, checked against the Gold bound t(n)
    (``encode correlations``): ``view`` ``"summary"`` (per pair), ``"values"`` (distinct values with
    counts) or ``"full"`` (every lag); and the one-line verdict."""
    one_of("view", view, CORRELATION_VIEWS)
    labels, x = codes.labels, codes.codes
    n_chips = x.shape[1]
    n, bound = gold_bound_of(n_chips)
    auto, cross = offpeak_counts(x)  # one pass over all pairs; the views below reuse or stream
    all_vals = sorted(set(auto) | set(cross))
    max_off = max((abs(v) for v in all_vals), default=0)
    within = None if bound is None else max_off <= bound
    meta = make_meta(
        "encode correlations",
        source=source,
        view=view,
        codes=len(labels),
        length=n_chips,
        degree=n,
        gold_bound=bound,
        max_offpeak=max_off,
        within_gold_bound=within,
        offpeak_values=all_vals,
        definition="R_ab[l] = sum_t a_t b_(t+l mod N), bipolar chips; auto peak (a=b, l=0) excluded",
        input_meta=codes.meta,
    )
    if view == "summary":
        columns: tuple[str, ...] = (
            "code_a",
            "code_b",
            "kind",
            "values",
            "max_offpeak",
            "gold_bound",
            "within_bound",
        )
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
            for p in summarize(x)
        ]
    elif view == "values":
        columns, rows = (
            ("value", "auto_count", "cross_count"),
            [(v, auto.get(v, 0), cross.get(v, 0)) for v in all_vals],
        )
    else:
        columns = ("code_a", "code_b", "lag", "value")
        rows = [
            (labels[a], labels[a + j], lag, int(v))
            for a, block in correlation_rows(x)
            for j, r in enumerate(block)
            for lag, v in enumerate(r)
        ]
    verdict = "" if bound is None else f"; Gold bound t({n}) = {bound}: {'within' if within else 'EXCEEDED'}"
    note = f"{len(labels)} codes of {n_chips} chips; off-peak values {all_vals}; max |R| = {max_off}{verdict}"
    return Table(columns=columns, rows=rows, meta=meta), note


def correlation_curves(
    codes: CodeSet, max_codes: int = 3
) -> tuple[np.ndarray, np.ndarray, list[str], int | None]:
    """The curves of the correlation figure: ``(lags, R, names, t(n))`` for every pair of the first
    ``max_codes`` codes."""
    m = min(len(codes.labels), max_codes)
    r = periodic_correlation(codes.codes[:m])
    show = [(a, b) for a in range(m) for b in range(a, m)]
    names = [f"{codes.labels[a]}·{codes.labels[b]}" for a, b in show]
    n_chips = codes.codes.shape[1]
    return np.arange(n_chips), np.stack([r[a, b] for a, b in show]), names, gold_bound_of(n_chips)[1]


# ------------------------------------------------------------------------------ mode signatures
def resolve_theta(theta: str | float, seed: int) -> float:
    """The carrier phase [rad]: a number, or ``"random"`` (uniform on [0, 2π) from trial 0 of ``seed``)."""
    if isinstance(theta, str) and theta.strip().lower() == "random":
        return float(trial_rng(integer("seed", seed, 0), 0).uniform(0.0, 2 * math.pi))
    try:
        value = float(theta)
    except ValueError:
        raise ConfigError("theta", theta, "is not a phase in radians or 'random'") from None
    if not math.isfinite(value):
        raise ConfigError("theta", theta, "is not a finite phase in radians")
    return value


def signature_table(
    mode: int,
    codes: str,
    config: SignatureConfig,
    *,
    length: int | None = None,
    zdot: str = "analytic",
    seed: int = 0,
    theta_option: str = "",
) -> tuple[Table, Signature]:
    """A sampled mode signature z_k = p_k[τ] cos(2π(f_c + f_d)t_k + θ), its replicas and derivatives
    (``encode signature``; the paper's eqs 1–3), for the code of Table I mode ``mode``.

    ``length`` samples (default one code period n_ρ m_ρ, at most :data:`~motionsig_cli.signals.signature.MAX_SAMPLES`); ``seed`` and
    ``theta_option`` are recorded (``theta_option`` is the phase as given, e.g. ``"random"``).
    """
    from motionsig_cli.signals import modes
    from motionsig_cli.signals.signature import MAX_SAMPLES, mode_signature

    bits = modes.table1_code(mode, codes)  # type: ignore[arg-type]
    one_of("zdot", zdot, ZDOT)
    if length is None:
        n = bits.size * int(config.m_rho)
        if n > MAX_SAMPLES:
            raise ConfigError(
                "m_rho", config.m_rho, f"gives {n} samples per code period, more than {MAX_SAMPLES}: lower it"
            )
    elif integer("length", length) < 1 or length > MAX_SAMPLES:
        raise ConfigError("length", length, f"is not a number of samples in [1, {MAX_SAMPLES}]")
    try:
        sig = mode_signature(to_bipolar(bits), config, length, zdot)  # type: ignore[arg-type]
    except ConfigError:
        raise
    except ValueError:  # non-finite samples: the phase 2π(f_c + f_d)·kT (or kT itself) overflows
        raise ConfigError(
            "T", config.T, "gives non-finite samples over this record: lower T, f_c or f_d"
        ) from None
    meta = make_meta(
        "encode signature",
        mode=mode,
        codes=codes,
        T=config.T,
        m_rho=config.m_rho,
        f_c=config.f_c,
        f_d=config.f_d,
        theta=config.theta,
        theta_option=theta_option,
        tau=config.tau,
        length=int(sig.k.size),
        zdot=zdot,
        seed=seed,
        assumptions="assumed: T = 0.05 s and m_rho = 20 samples per chip (the defaults); the paper does not "
        "state them",
        equations=f"eqs (1)-(3) of {MODE_PAPER}",
    )
    columns = ("k", "t", "chip", "p", "z", "z_cos", "z_sin", "zdot", "zdot_cos", "zdot_sin")
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
    return Table(columns=columns, rows=rows, meta=meta), sig
