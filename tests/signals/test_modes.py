"""Table I (seed 000): printed strings, corrected Gold codes, errata."""

import numpy as np

from motionsig_cli.signals import modes
from motionsig_cli.signals.correlation import periodic_correlation, to_bipolar
from tests.oracles import berlekamp_massey

# Spec §1.9 table "Gold code" column (derived by the spec authors; re-derived here by search).
SPEC_CORRECTED = [
    "1100001010111001011011000011011",
    "1100100001011100110111001110100",
    "1010110111011001011110111101010",
]
# Seed 000, Table I, as printed (also in data/table1.csv).
SEED_PRINTED = [
    "1100001010111001011011000011011",
    "1100100001011101110111001110100",
    "1010110110110010111101110101010",
]


def test_printed_data_is_the_seed_table():
    assert [modes.bit_string(c) for c in modes.printed_codes()] == SEED_PRINTED


def test_corrected_codes_equal_spec():
    """Spec target E2."""
    assert [modes.bit_string(c) for c in modes.corrected_codes()] == SPEC_CORRECTED


def test_errata_structure():
    """E2: mode 1 printed exactly; mode 2 differs only at chip 15; mode 3 = gold[0:7]+gold[8:25]+'0'+gold[25:31]."""
    p, g = SEED_PRINTED, SPEC_CORRECTED
    assert p[0] == g[0]
    assert [i for i in range(31) if p[1][i] != g[1][i]] == [15]
    assert p[2] == g[2][0:7] + g[2][8:25] + "0" + g[2][25:31]


def test_nearest_member_search_recovers_stored_members():
    """Exhaustive search over the 33 × 31 members re-derives (k, a) = (9, 8), (13, 13), (25, 12)
    with edit distances 0, 1, 2, uniquely."""
    found = modes.nearest_members(modes.printed_codes())
    assert [(m.index, m.shift) for m in found] == modes.corrected_members() == [(9, 8), (13, 13), (25, 12)]
    assert [m.edit_distance for m in found] == [0, 1, 2]
    assert [m.hamming for m in found] == [0, 1, 9]
    assert all(m.ties == 1 for m in found)


def test_linear_complexity_evidence():
    """Spec §1.9: mode 1 has linear complexity 10 (a sum of two degree-5 m-sequences); the printed
    modes 2 and 3 have full complexity (not LFSR sequences). Berlekamp–Massey over two periods."""
    lc = [berlekamp_massey(np.tile(c, 2))[0] for c in modes.printed_codes()]
    assert lc[0] == 10 and lc[1] > 10 and lc[2] > 10
    assert all(berlekamp_massey(np.tile(c, 2))[0] == 10 for c in modes.corrected_codes())


def test_correlations_corrected_vs_printed():
    """E3: corrected codes three-valued {−9, −1, 7}; printed codes 2 and 3 violate it
    (spec §1.9 lists R22 = {−9, −5, −1, 3, 7, 11}, R13 reaching 17)."""
    rc = periodic_correlation(to_bipolar(modes.corrected_codes()))
    vals = {int(v) for i in range(3) for j in range(i, 3) for v in (rc[i, j, 1:] if i == j else rc[i, j])}
    assert vals == {-9, -1, 7}
    rp = periodic_correlation(to_bipolar(modes.printed_codes()))
    assert set(np.unique(rp[1, 1, 1:]).tolist()) == {-9, -5, -1, 3, 7, 11}
    assert set(np.unique(rp[0, 2]).tolist()) == {-11, -7, -3, 1, 5, 9, 17}


def test_weights():
    """Spec §1.9: mode 1 and corrected mode 2 have 16 ones, corrected mode 3 has 20; printed mode 3 has 19."""
    assert modes.corrected_codes().sum(axis=1).tolist() == [16, 16, 20]
    assert int(modes.printed_codes()[2].sum()) == 19


def test_family_weights_exclude_printed_mode3():
    """Gold-code weights for odd n are 2ⁿ⁻¹ and 2ⁿ⁻¹ ± 2^((n−1)/2) (Sarwate & Pursley 1980): {12, 16, 20}
    for n = 5, so the printed mode 3 (19 ones) cannot be a member of any cyclic shift of the family."""
    from motionsig_cli.signals import gold

    _, fam = gold.gold_family(0o45, 0o75)
    assert set(fam.sum(axis=1).tolist()) == {12, 16, 20}
