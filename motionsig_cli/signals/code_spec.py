"""The codes of the modes, written as one short text (``--codes`` of ``simulate`` and ``detect``).

Mode i carries the i-th code of the set (eqs 1–3 of the mode-signature paper, 47th IEEE CDC, Cancún, 2008: the signature of mode i spreads its carrier with code i). A set is

- ``corrected`` or ``printed``: Table I of the paper (3 codes of 31 chips; the corrected Gold codes, or
  the strings as printed, see ``motionsig encode table1 --view errata``);
- ``gold:P1,P2``: the Gold family of the preferred pair P1, P2 (octal, ``45``, or exponents,
  ``x^5+x^2+1``, as ``encode gold`` takes them; registers start at 0…01), all 2ⁿ + 1 members in the
  order ``encode gold --all`` lists them (u, v, then u ⊕ Tᵏv for k = 0 … 2ⁿ − 2);
  ``gold:P1,P2:K`` the first K of them; ``gold:P1,P2:MEMBERS`` chosen members, a comma-separated list
  of member indices as ``encode gold --index`` takes them (−2 or ``u``, −1 or ``v``, k ≥ 0), ranges
  ``a-b`` of indices ≥ 0, each optionally with a start offset ``k@a`` (``encode gold --shift``). A single
  plain number is a count; one member alone is written with its offset, ``7@0``. Table I's corrected
  codes are ``gold:45,75:9@8,13@13,25@12``;
- ``mseq:P[,P…]``: the m-sequences of primitive polynomials of one degree (``encode mseq``), each
  optionally with a cyclic shift ``P@a``;
- ``gps:PRNS``: GPS L1 C/A codes (1023 chips, IS-GPS-200), PRNs 1–32 as a list with ranges, ``1-3,7``;
- a path to a code table as ``encode`` writes it (the long table ``code,chip,value``, chips 0/1 or ±1;
  ``file:PATH`` when the path could be read as one of the forms above).

All codes of a set have the same length. A malformed text is a :class:`~motionsig_cli.config.ConfigError`
naming ``codes``; a bad code table an :class:`~motionsig_cli.errors.InputError` naming its file and line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from motionsig_cli.config import ConfigError

__all__ = ["MAX_CODE_CHIPS", "SYNTAX", "ModeCodes", "parse_codes"]

MAX_CODE_CHIPS = 1 << 22
"""Most chips of a code set (modes × chips per code): a larger set is refused before it is built."""
SYNTAX = (
    "corrected, printed, gold:P1,P2[:K or :MEMBERS], mseq:P[,P...], gps:PRNS, or a code table file "
    "(code,chip,value as 'motionsig encode' writes it)"
)
BUILTIN = "corrected, printed, gold:P1,P2[:K or :MEMBERS], mseq:P[,P...] or gps:PRNS"
NO_FILES = "a record's metadata never names a file: give a code table file on the command line (--codes FILE)"
_INT = re.compile(r"-?\d+")
_RANGE = re.compile(r"(\d+)-(\d+)")


@dataclass(frozen=True, eq=False)
class ModeCodes:
    """A code set: one bipolar code per mode.

    Attributes:
        spec: The set as text, normalised (polynomials in octal): what the metadata records and what
            :func:`parse_codes` reads back to the same chips.
        chips: Bipolar chips, ``(n_modes, n_chips)`` floats ±1.
        names: One label per mode (``gold_k3``, ``PRN7``, the code table's labels …).
    """

    spec: str
    chips: np.ndarray
    names: tuple[str, ...]

    @property
    def n_modes(self) -> int:
        return int(self.chips.shape[0])

    @property
    def n_chips(self) -> int:
        return int(self.chips.shape[1])


def parse_codes(text: str, *, files: bool = True) -> ModeCodes:
    """The code set that ``text`` names (see the module docstring).

    ``files=False`` for a text that is data, not a command line (a record's metadata): it may name a
    built-in set only; a path (``file:PATH`` or a bare one) is refused without being looked at. Files
    come from the command line only (``--codes FILE``).

    Raises:
        ConfigError: naming ``codes``: malformed text, a polynomial that is not primitive or a pair that is
            not preferred, a member or PRN out of range or listed twice, codes of different lengths, or a
            set of more than :data:`MAX_CODE_CHIPS` chips.
        InputError: a code table file that cannot be read or is malformed (file and line named).

    Examples:
        >>> from motionsig_cli import parse_codes
        >>> c = parse_codes("gold:45,75:9@8,13@13,25@12")  # Table I's corrected codes
        >>> c.n_modes, c.n_chips, c.names[0]
        (3, 31, 'gold_k9_a8')
    """
    if not isinstance(text, str):
        raise ConfigError("codes", text, f"is not text: write one of {SYNTAX}")
    raw = text.strip()
    kind, sep, rest = raw.partition(":")
    kind = kind.lower()
    if raw.lower() in ("corrected", "printed"):
        return _table1(raw.lower())
    if sep and kind == "file":
        if not files:
            raise ConfigError(
                "codes", _clip(text), f"names a file, not a built-in code set ({BUILTIN}); {NO_FILES}"
            )
        return _file(rest)
    if sep and kind in ("gold", "mseq", "gps") and not (files and Path(raw).is_file()):
        return {"gold": _gold, "mseq": _mseq, "gps": _gps}[kind](raw, rest)
    if not files:
        raise ConfigError("codes", _clip(text), f"is not a built-in code set ({BUILTIN}); {NO_FILES}")
    if raw and raw != "-" and Path(raw).is_file():
        return _file(raw)
    what = "is not a code set" if sep else "is neither a code set nor an existing file"
    raise ConfigError("codes", text, f"{what}: write one of {SYNTAX}")


def _clip(text: str, limit: int = 80) -> str:
    """``text`` cut to ``limit`` characters (a record's value quoted in a message)."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _bipolar(bits: np.ndarray) -> np.ndarray:
    from motionsig_cli.signals.correlation import to_bipolar

    return to_bipolar(np.asarray(bits)).astype(float)


def _table1(variant: str) -> ModeCodes:
    from motionsig_cli.signals.modes import table1_codes

    chips = _bipolar(table1_codes(variant))  # type: ignore[arg-type]
    return ModeCodes(variant, chips, tuple(f"mode{i + 1}" for i in range(chips.shape[0])))


def _size(text: str, n_modes: int, n_chips: int) -> None:
    if n_chips < 2:
        raise ConfigError("codes", text, f"has codes of {n_chips} chip: a code needs at least 2 chips")
    if n_modes * n_chips > MAX_CODE_CHIPS:
        raise ConfigError(
            "codes",
            text,
            f"is {n_modes} codes of {n_chips} chips, more than {MAX_CODE_CHIPS} chips in all: choose fewer "
            "members or a lower degree",
        )


def _offset(text: str, entry: str) -> tuple[str, int | None]:
    """``k@a`` → (``k``, a); ``k`` → (``k``, None)."""
    head, at, tail = entry.partition("@")
    if not at:
        return head, None
    if not _INT.fullmatch(tail):
        raise ConfigError("codes", text, f"has a bad offset in {entry!r}: write index@offset, e.g. 7@3")
    return head, int(tail)


def _entries(text: str, body: str, what: str) -> list[str]:
    parts = [p.strip() for p in body.split(",")]
    if not body.strip() or any(not p for p in parts):
        raise ConfigError(
            "codes", text, f"has an empty {what} (a comma-separated list, e.g. {_EXAMPLE[what]})"
        )
    return parts


_EXAMPLE = {"polynomial": "gold:45,75", "member": "gold:45,75:0,3,7", "PRN": "gps:1-3,7"}


def _gold(text: str, rest: str) -> ModeCodes:
    from motionsig_cli.signals import gf2
    from motionsig_cli.signals.gold import GoldConfig
    from motionsig_cli.signals.lfsr import m_sequence

    polys, sep, members = rest.partition(":")
    pair = _entries(text, polys, "polynomial")
    if len(pair) != 2:
        raise ConfigError(
            "codes",
            text,
            f"names {len(pair)} polynomial{'' if len(pair) == 1 else 's'}: a Gold family needs a pair, P1,P2",
        )
    try:
        cfg = GoldConfig(pair[0], pair[1])
    except ConfigError as exc:
        raise ConfigError("codes", text, f"is not a Gold family: {exc.field} {exc.detail}") from None
    n_chips = (1 << cfg.degree) - 1
    family = [-2, -1, *range(n_chips)]  # the order of encode gold --all
    chosen: list[tuple[int, int]]
    if not sep:
        chosen = [(k, 0) for k in family]
    elif re.fullmatch(r"\d+", members.strip()):
        count = int(members)
        if not 1 <= count <= len(family):
            raise ConfigError(
                "codes", text, f"asks for {count} members: the family has 1 to {len(family)} (2^n + 1)"
            )
        chosen = [(k, 0) for k in family[:count]]
    else:
        chosen = []
        for entry in _entries(text, members, "member"):
            head, shift = _offset(text, entry)
            head = head.strip().lower()
            if head in ("u", "v"):
                ks = [-2 if head == "u" else -1]
            elif _INT.fullmatch(head):
                ks = [int(head)]
            elif (m := _RANGE.fullmatch(head)) is not None and int(m.group(1)) <= int(m.group(2)):
                ks = [int(m.group(1)), int(m.group(2))]  # the ends checked below, then filled in
            else:
                raise ConfigError(
                    "codes", text, f"has a bad member {entry!r}: an index (-2..{n_chips - 1}, u, v), a range "
                    "a-b or index@offset",
                )  # fmt: skip
            for k in ks:
                if not -2 <= k <= n_chips - 1:
                    indices = f"-2 (u), -1 (v) and 0..{n_chips - 1}"
                    raise ConfigError(
                        "codes",
                        text,
                        f"names member {k}: the indices of a degree-{cfg.degree} family are {indices}",
                    )
            chosen.extend((k, shift or 0) for k in range(ks[0], ks[-1] + 1))
            _size(text, len(chosen), n_chips)
        seen: set[tuple[int, int]] = set()
        for k, a in chosen:
            if (k, a % n_chips) in seen:
                raise ConfigError("codes", text, f"lists member {k}@{a} twice")
            seen.add((k, a % n_chips))
    _size(text, len(chosen), n_chips)
    u, v = m_sequence(int(cfg.poly1), cfg.init1), m_sequence(int(cfg.poly2), cfg.init2)
    rows = [_member(u, v, k, a) for k, a in chosen]
    p1, p2 = gf2.to_octal(int(cfg.poly1)), gf2.to_octal(int(cfg.poly2))
    spec = f"gold:{p1},{p2}" + (f":{members.strip().lower().replace(' ', '')}" if sep else "")
    names = tuple(f"gold_k{k}" + (f"_a{a}" if a else "") for k, a in chosen)
    return ModeCodes(spec, _bipolar(np.stack(rows)), names)


def _member(u: np.ndarray, v: np.ndarray, k: int, shift: int) -> np.ndarray:
    code = u if k == -2 else v if k == -1 else u ^ np.roll(v, -k)
    return np.roll(code, -shift)


def _mseq(text: str, rest: str) -> ModeCodes:
    from motionsig_cli.signals import gf2
    from motionsig_cli.signals.lfsr import m_sequence, primitive_polynomial

    polys: list[tuple[int, int]] = []
    for entry in _entries(text, rest, "polynomial"):
        head, shift = _offset(text, entry)
        try:
            poly = primitive_polynomial(head.strip(), "poly")
        except ConfigError as exc:
            raise ConfigError("codes", text, f"has a bad polynomial: {exc.detail}") from None
        polys.append((poly, shift or 0))
    degrees = sorted({gf2.degree(p) for p, _ in polys})
    if len(degrees) > 1:
        raise ConfigError(
            "codes", text, f"mixes degrees {degrees}: the codes of the modes must have the same length"
        )
    n_chips = (1 << degrees[0]) - 1
    if len({(p, a % n_chips) for p, a in polys}) != len(polys):
        raise ConfigError("codes", text, "lists a polynomial (with the same shift) twice")
    _size(text, len(polys), n_chips)
    rows = [m_sequence(p, None, a) for p, a in polys]
    spec = "mseq:" + ",".join(gf2.to_octal(p) + (f"@{a}" if a else "") for p, a in polys)
    names = tuple(f"mseq_{gf2.to_octal(p)}" + (f"_a{a}" if a else "") for p, a in polys)
    return ModeCodes(spec, _bipolar(np.stack(rows)), names)


def _gps(text: str, rest: str) -> ModeCodes:
    from motionsig_cli.signals import gps

    known = sorted(gps.phase_selectors())
    prns: list[int] = []
    for entry in _entries(text, rest, "PRN"):
        if re.fullmatch(r"\d+", entry):
            lo = hi = int(entry)
        elif (m := _RANGE.fullmatch(entry)) is not None:
            lo, hi = int(m.group(1)), int(m.group(2))
        else:
            raise ConfigError("codes", text, f"has a bad PRN {entry!r}: a number, or a range like 1-3")
        if lo > hi or lo < known[0] or hi > known[-1]:
            raise ConfigError("codes", text, f"names PRN {entry}: the C/A PRNs are {known[0]}-{known[-1]}")
        for p in range(lo, hi + 1):
            if p in prns:
                raise ConfigError("codes", text, f"lists PRN {p} twice")
            prns.append(p)
    rows = gps.ca_codes(prns)
    spec = "gps:" + ",".join(str(p) for p in prns)
    return ModeCodes(spec, _bipolar(rows), tuple(f"PRN{p}" for p in prns))


def _file(path: str) -> ModeCodes:
    from motionsig_cli.signals.code_sets import load_codes

    if not path.strip() or path.strip() == "-":
        raise ConfigError("codes", path, "is not a file name (a code table cannot be read from stdin here)")
    codes = load_codes(path)
    _size(path, *codes.codes.shape)
    return ModeCodes(path, codes.codes.astype(float), tuple(codes.labels))
