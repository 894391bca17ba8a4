"""Polynomials given to the public code functions as text are read as the command line reads ``--poly1 45``
(octal, or exponents); an ``int`` stays the bit mask (``0o45``)."""

from __future__ import annotations

import numpy as np
import pytest

from motionsig_cli import ConfigError, gold_code, gold_family, m_sequence
from motionsig_cli.signals.gold import GoldConfig
from motionsig_cli.signals.lfsr import MSequenceConfig


@pytest.mark.parametrize("text", ["45", "0o45", "x^5+x^2+1"])
def test_text_polynomials_are_the_command_lines(text: str) -> None:
    # oracle: the configs the command line builds from --poly 45 / --poly1 45 --poly2 75
    assert np.array_equal(m_sequence(text), MSequenceConfig(text).sequence())
    idx, codes = gold_family(text, "75")
    ref_idx, ref_codes = GoldConfig(text, "75").family()
    assert np.array_equal(idx, ref_idx) and np.array_equal(codes, ref_codes)
    assert np.array_equal(gold_code(text, "75", 9, 8), GoldConfig(text, "75").member(9, 8))


def test_an_int_is_the_bit_mask() -> None:
    assert np.array_equal(gold_family("45", "75")[1], gold_family(0o45, 0o75)[1])
    # the decimal 45 (0b101101 = x^5 + x^3 + x^2 + 1) is another polynomial, not the octal 45
    with pytest.raises(ConfigError):
        gold_family(45, 75)


@pytest.mark.parametrize(("args", "field"), [(("48", "75"), "poly1"), (("45", "x^5+x^9"), "poly2")])
def test_bad_text_names_its_argument(args: tuple[str, str], field: str) -> None:
    with pytest.raises(ConfigError) as exc:
        gold_family(*args)
    assert exc.value.field == field
