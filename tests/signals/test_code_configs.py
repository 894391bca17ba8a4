"""The checked entry points of the code generators: each bad field is a ConfigError naming it."""

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.signals import gf2, gold, modes
from motionsig_cli.signals.lfsr import MSequenceConfig, m_sequence, parse_state, primitive_polynomial

DEG8 = {"poly1": "x^8+x^4+x^3+x^2+1", "poly2": "x^8+x^6+x^5+x^3+1"}


@pytest.mark.parametrize(
    ("fields", "field", "text"),
    [
        ({"poly": "44"}, "poly", "is not primitive (x^5+x^2 = octal 44)"),
        ({"poly": "x^5+y"}, "poly", "is malformed: term 'y'"),
        ({"poly": "x^5+x^5+1"}, "poly", "term x^5 appears twice"),
        ({"poly": ""}, "poly", "is empty"),
        ({"poly": 1}, "poly", "has degree < 1"),
        ({"poly": "x^40+1"}, "poly", "has degree 40 > 32"),
        ({"poly": "x^25+x^3+1"}, "poly", "has degree 25 > 20"),
        ({"init": "0001"}, "init", "has 4 bits; a degree-5 register needs 5 bits"),
        ({"init": "00000"}, "init", "is all zeros"),
        ({"init": "0012a"}, "init", "may contain only 0 and 1"),
        ({"init": "\u0660\u0660\u0660\u0660\u0661"}, "init", "may contain only 0 and 1"),
        ({"shift": 1.5}, "shift", "is not an integer"),
        ({"shift": True}, "shift", "is not an integer"),
    ],
)
def test_msequence_config_names_the_bad_field(fields, field, text):
    with pytest.raises(ConfigError) as exc:
        MSequenceConfig(**fields)
    assert exc.value.field == field and text in str(exc.value)


def test_msequence_config_normalises_and_matches_m_sequence():
    cfg = MSequenceConfig("x^5+x^2+1", "01101", 3)
    assert cfg.poly == 0o45 and cfg.init == (0, 1, 1, 0, 1) and cfg.degree == 5
    assert np.array_equal(cfg.sequence(), m_sequence(0o45, "01101", 3))
    assert MSequenceConfig().init == (0, 0, 0, 0, 1)


@pytest.mark.parametrize(
    ("fields", "field", "text"),
    [
        ({"poly1": "44"}, "poly1", "is not primitive"),
        ({"poly2": "x^5+y"}, "poly2", "is malformed"),
        ({"poly1": "x^25+x^3+1"}, "poly1", "has degree 25 > 20"),
        (
            {"poly2": "51"},
            "poly2",
            "'51' is not a preferred partner of 45: the cross-correlation takes [-9, -5",
        ),
        (DEG8, "poly1", "has degree 8, which is a multiple of 4"),
        ({"poly1": "x^2+x+1", "poly2": "x^2+x+1"}, "poly1", "has degree 2, which is < 3"),
        ({"poly2": "x^6+x+1"}, "poly2", "has degree 6, not the degree 5 of poly1"),
        ({"poly2": "x^6+x+1", "preferred": False}, "poly2", "not the degree 5 of poly1"),
        ({"poly2": "44", "preferred": False}, "poly2", "is not primitive"),
        ({"init1": "0000"}, "init1", "has 4 bits"),
        ({"init2": "00000"}, "init2", "is all zeros"),
        ({"init2": "0101x"}, "init2", "may contain only 0 and 1"),
    ],
)
def test_gold_config_names_the_bad_field(fields, field, text):
    with pytest.raises(ConfigError) as exc:
        gold.GoldConfig(**fields)
    assert exc.value.field == field and text in str(exc.value)


@pytest.mark.parametrize(
    ("index", "shift", "field"), [(31, 0, "index"), (-3, 0, "index"), (1.5, 0, "index"), (0, 0.5, "shift")]
)
def test_gold_member_names_index_and_shift(index, shift, field):
    with pytest.raises(ConfigError) as exc:
        gold.GoldConfig().member(index, shift)
    assert exc.value.field == field


def test_gold_config_members_and_family_match_the_functions():
    cfg = gold.GoldConfig("45", "x^5+x^4+x^3+x^2+1", "00001", "10011")
    assert cfg.poly2 == 0o75 and cfg.init2 == (1, 0, 0, 1, 1) and cfg.degree == 5
    assert np.array_equal(cfg.member(9, 8), gold.gold_code(0o45, 0o75, 9, 8, "00001", "10011"))
    idx, fam = cfg.family()
    ref_idx, ref = gold.gold_family(0o45, 0o75, "00001", "10011")
    assert np.array_equal(idx, ref_idx) and np.array_equal(fam, ref)


def test_unchecked_family_is_the_stack_of_unchecked_members():
    """preferred=False (MATLAB's behaviour, ``encode gold --unchecked --all``): member k of the family
    is gold_code(..., k, verify=False) for every k."""
    idx, fam = gold.GoldConfig("45", "51", preferred=False).family()
    assert idx.tolist() == list(range(-2, 31))
    ref = np.stack([gold.gold_code(0o45, 0o51, int(k), 0, verify=False) for k in idx])
    assert np.array_equal(fam, ref)
    with pytest.raises(ConfigError, match="not a preferred partner"):
        gold.gold_family(0o45, 0o51)
    assert np.array_equal(gold.gold_family(0o45, 0o51, verify=False)[1], fam)


@pytest.mark.parametrize(("n", "text"), [(2, "is < 3"), (8, "multiple of 4"), (15, "is > 13")])
def test_pair_search_degree(n, text):
    with pytest.raises(ConfigError, match=text) as exc:
        gold.preferred_pairs(n)
    assert exc.value.field == "degree"


def test_library_functions_name_their_argument():
    with pytest.raises(ConfigError) as exc:
        gf2.parse_polynomial("x^5+q", "code")
    assert exc.value.field == "code"
    with pytest.raises(ConfigError, match="poly1 = '44' is not primitive") as exc:
        gold.check_pair(0o44, 0o45)
    with pytest.raises(ConfigError) as exc:
        parse_state("11", 5, "init2")
    assert exc.value.field == "init2"
    with pytest.raises(ConfigError) as exc:
        primitive_polynomial("x^13+x^4+x^3+x+1", "poly1", max_degree=12)
    assert exc.value.field == "poly1" and "degree 13 > 12" in str(exc.value)


@pytest.mark.parametrize(
    ("mode", "variant", "field"),
    [
        (0, "corrected", "mode"),
        (4, "printed", "mode"),
        (True, "corrected", "mode"),
        (1, "as-printed", "codes"),
    ],
)
def test_table1_code_names_mode_and_variant(mode, variant, field):
    with pytest.raises(ConfigError) as exc:
        modes.table1_code(mode, variant)
    assert exc.value.field == field


@pytest.mark.parametrize("variant", ["corrected", "printed"])
def test_table1_code_is_the_row_of_table1_codes(variant):
    for m in (1, 2, 3):
        assert np.array_equal(modes.table1_code(m, variant), modes.table1_codes(variant)[m - 1])
