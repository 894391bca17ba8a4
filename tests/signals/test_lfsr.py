"""m-sequences: MATLAB vectors, balance, runs, two-valued autocorrelation, recurrence."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motionsig_cli.signals import gf2
from motionsig_cli.signals.correlation import periodic_correlation, to_bipolar
from motionsig_cli.signals.lfsr import m_sequence, parse_state
from tests.oracles import berlekamp_massey


def _s(bits):
    return "".join(map(str, bits))


def test_matlab_pn_vector():
    """Spec target E1: MATLAB comm.PNSequence, x⁵+x²+1, InitialConditions [0 0 0 0 1]."""
    assert _s(m_sequence(0o45, "00001")) == "1000010010110011111000110111010"


def test_default_state_is_matlab_default():
    assert np.array_equal(m_sequence(0o45), m_sequence(0o45, "00001"))


def test_first_chips_are_reversed_state():
    assert _s(m_sequence(0o45, "01101")[:5]) == "10110"


@pytest.mark.parametrize("bad", ["0000", "000001", "00000", "0012a"])
def test_bad_states(bad):
    with pytest.raises(ValueError):
        parse_state(bad, 5)


def test_non_primitive_rejected():
    with pytest.raises(ValueError, match="not primitive"):
        m_sequence(0b11111)


def _runs(bits):
    """Cyclic runs as (value, length), starting at a value change."""
    b = np.asarray(bits)
    start = int(np.flatnonzero(b != np.roll(b, 1))[0])
    b = np.roll(b, -start)
    runs, cur, length = [], b[0], 0
    for x in b:
        if x == cur:
            length += 1
        else:
            runs.append((int(cur), length))
            cur, length = x, 1
    runs.append((int(cur), length))
    return runs


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=3, max_value=11), st.data())
def test_m_sequence_properties(n, data):
    """Golomb's postulates for any primitive polynomial, state and shift (Golomb 1967, ch. III)."""
    p = data.draw(st.sampled_from(gf2.primitive_polynomials(n)))
    state = data.draw(st.lists(st.integers(0, 1), min_size=n, max_size=n).filter(any))
    shift = data.draw(st.integers(0, 2**n))
    s = m_sequence(p, state, shift)
    period = 2**n - 1
    assert s.size == period
    # balance: 2^(n-1) ones
    assert int(s.sum()) == 2 ** (n - 1)
    # run distribution: 2^(n-k-2) runs of each value for k <= n-2, one run of n ones, one of n-1 zeros
    runs = _runs(s)
    for k in range(1, n - 1):
        for v in (0, 1):
            assert sum(1 for r in runs if r == (v, k)) == 2 ** (n - k - 2)
    assert runs.count((1, n)) == 1 and runs.count((0, n - 1)) == 1
    # two-valued autocorrelation: N at lag 0, -1 elsewhere
    r = periodic_correlation(to_bipolar(s)[None, :])[0, 0]
    assert r[0] == period and np.all(r[1:] == -1)
    # the linear recurrence of the polynomial, checked from its definition
    taps = [i for i in range(n) if p >> i & 1]
    ext = np.concatenate([s, s[:n]])
    for t in range(period):
        assert ext[t + n] == np.bitwise_xor.reduce(ext[[t + i for i in taps]])
    # shift is a cyclic advance
    assert np.array_equal(s, np.roll(m_sequence(p, state), -shift))
    # Berlekamp–Massey oracle: linear complexity n, minimal polynomial = reciprocal of p
    length, conn = berlekamp_massey(s[: 2 * n + 4])
    assert length == n and gf2.reciprocal(conn) == p
