"""Preferred pairs and Gold families."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motionsig_cli.signals import gf2, gold
from motionsig_cli.signals.correlation import periodic_correlation, to_bipolar
from motionsig_cli.signals.lfsr import m_sequence
from tests.oracles import berlekamp_massey, naive_periodic_correlation


def _s(bits):
    return "".join(map(str, bits))


def test_matlab_gold_vectors_non_preferred_pair():
    """Spec target E1: MATLAB comm.GoldSequence vectors (quoted in the mhostetter/sdr tests) for the
    pair x⁵+x²+1, x⁵+x³+1 (octal 45/51), both states 00001, Index 0 and 1. MATLAB does not check the
    pair; 45/51 is a reciprocal pair and not preferred, so our default refuses it."""
    assert _s(gold.gold_code(0o45, 0o51, 0, verify=False)) == "0000000111000101110111010001110"
    assert _s(gold.gold_code(0o45, 0o51, 1, verify=False)) == "1000111001011111100111111010011"
    with pytest.raises(ValueError, match="not a preferred partner of 45"):
        gold.gold_code(0o45, 0o51, 0)


def test_mathworks_doc_example_prefix():
    """Spec §1.9: the MathWorks Gold Sequence Generator default-pair output begins 0000001011 1."""
    assert _s(gold.gold_code(0o45, 0o75, 0))[:11] == "00000010111"


def test_family_45_75_is_exactly_three_valued():
    """Spec target E3: all 33 members, every off-peak auto and cross correlation in {−9, −1, 7}."""
    idx, fam = gold.gold_family(0o45, 0o75)
    assert fam.shape == (33, 31) and list(idx[:3]) == [-2, -1, 0]
    r = periodic_correlation(to_bipolar(fam))
    off = np.concatenate([r[i, i, 1:] for i in range(33)] + [r[np.triu_indices(33, 1)].ravel()])
    assert set(np.unique(off).tolist()) == {-9, -1, 7}
    assert np.all(r[np.arange(33), np.arange(33), 0] == 31)


def test_fft_correlation_matches_definition():
    _, fam = gold.gold_family(0o45, 0o75)
    b = to_bipolar(fam[[0, 5, 20]])
    r = periodic_correlation(b)
    for i in range(3):
        for j in range(3):
            assert np.array_equal(r[i, j], naive_periodic_correlation(b[i], b[j]))


def test_degree5_pairs_match_spec():
    """Spec §1.9: 12 of the 15 degree-5 pairs are preferred; the reciprocal pairs 45/51, 57/75, 67/73
    are six-valued {−9, −5, −1, 3, 7, 11}."""
    pairs = {(gf2.to_octal(a), gf2.to_octal(b)) for a, b in gold.preferred_pairs(5)}
    assert len(pairs) == 12
    for a, b in [("45", "51"), ("57", "75"), ("67", "73")]:
        assert (a, b) not in pairs
        chk = gold.check_pair(int(a, 8), int(b, 8))
        assert chk.values == (-9, -5, -1, 3, 7, 11) and not chk.preferred
    assert ("45", "75") in pairs


@pytest.mark.parametrize("n", [3, 5, 6, 7, 9, 10, 11])
def test_decimation_theorem_pairs_are_listed(n):
    """Oracle from Gold's theorem (Sarwate & Pursley 1980, Thm 8): for u an m-sequence and
    q = 2ᵏ + 1 with gcd(n, k) = 1 (n odd) or 2 (n ≡ 2 mod 4), u and its decimation u[q·t] form a
    preferred pair. The partner's polynomial is found independently by Berlekamp–Massey."""
    listed = set(gold.preferred_pairs(n))
    need = 1 if n % 2 else 2
    ks = [k for k in range(1, n) if math.gcd(n, k) == need]
    period = 2**n - 1
    polys = gf2.primitive_polynomials(n)
    for p in polys[:: max(1, len(polys) // 6)]:  # a spread of base polynomials
        u = m_sequence(p)
        for k in ks:
            q = 2**k + 1
            dec = u[(q * np.arange(2 * n + 2)) % period]
            length, conn = berlekamp_massey(dec)
            partner = gf2.reciprocal(conn)
            assert length == n and gf2.is_primitive(partner)
            if partner != p:
                assert (min(p, partner), max(p, partner)) in listed


def test_degree_multiple_of_four_rejected():
    with pytest.raises(ValueError, match="multiple of 4"):
        gold.preferred_pairs(8)
    p = gf2.primitive_polynomials(8)
    with pytest.raises(ValueError, match="multiple of 4"):
        gold.gold_code(p[0], p[1], 0)


@settings(max_examples=25, deadline=None)
@given(st.sampled_from([3, 5, 6, 7, 9, 10]), st.data())
def test_random_members_stay_in_gold_values(n, data):
    """Any member (index, shift, initial states) of any listed pair correlates with any other member
    of the same family only in {−t(n), −1, t(n) − 2}."""
    a, b = data.draw(st.sampled_from(gold.preferred_pairs(n)))
    period = 2**n - 1
    s1 = data.draw(st.lists(st.integers(0, 1), min_size=n, max_size=n).filter(any))
    s2 = data.draw(st.lists(st.integers(0, 1), min_size=n, max_size=n).filter(any))
    k1, k2 = data.draw(st.integers(-2, period - 1)), data.draw(st.integers(-2, period - 1))
    sh1, sh2 = data.draw(st.integers(0, period - 1)), data.draw(st.integers(0, period - 1))
    c1 = to_bipolar(gold.gold_code(a, b, k1, sh1, s1, s2))
    c2 = to_bipolar(gold.gold_code(a, b, k2, sh2, s1, s2))
    r = periodic_correlation(np.stack([c1, c2]))
    allowed = set(gold.gold_values(n))
    assert set(np.unique(r[0, 0, 1:]).tolist()) <= allowed
    if k1 != k2:  # different members are never cyclic shifts of each other: no peak anywhere
        assert set(np.unique(r[0, 1]).tolist()) <= allowed


def test_index_out_of_range():
    with pytest.raises(ValueError, match="index"):
        gold.gold_code(0o45, 0o75, 31)
