"""GF(2) polynomials: parsing and primitivity."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from motionsig_cli.signals import gf2
from tests.oracles import euler_phi


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("45", 0o45),
        ("0o75", 0o75),
        ("x^5+x^2+1", 0o45),
        ("1 + x^3 + x^10", (1 << 10) | 8 | 1),
        ("x**3+x+1", 0b1011),
    ],
)
def test_parse_forms(text, value):
    assert gf2.parse_polynomial(text) == value


@pytest.mark.parametrize("text", ["", "x^5+y+1", "x^5+x^5+1", "9", "x^^2+1", "1", "x^40+1"])
def test_parse_rejects_malformed(text):
    with pytest.raises(ValueError):
        gf2.parse_polynomial(text)


def test_octal_exponent_round_trip():
    for p in gf2.primitive_polynomials(7):
        assert gf2.parse_polynomial(gf2.to_exponents(p)) == p
        assert gf2.parse_polynomial(gf2.to_octal(p)) == p


@pytest.mark.parametrize("n", range(2, 13))
def test_number_of_primitive_polynomials_is_phi_over_n(n):
    """Oracle: there are φ(2ⁿ − 1)/n primitive polynomials of degree n (Lidl & Niederreiter Thm 3.5)."""
    assert len(gf2.primitive_polynomials(n)) == euler_phi(2**n - 1) // n


def test_degree5_primitive_set_matches_spec():
    """Spec §1.9: the degree-5 primitive polynomials are octal 45, 51, 57, 67, 73, 75."""
    assert [gf2.to_octal(p) for p in gf2.primitive_polynomials(5)] == ["45", "51", "57", "67", "73", "75"]


def test_irreducible_but_not_primitive():
    """x⁴+x³+x²+x+1 is irreducible but x has order 5, not 15."""
    assert not gf2.is_primitive(0b11111)
    assert not gf2.is_primitive(0o44)  # no constant term
    with pytest.raises(ValueError, match="not primitive"):
        gf2.require_primitive(0b11111)


@given(st.integers(min_value=2, max_value=11), st.data())
def test_reciprocal_of_primitive_is_primitive(n, data):
    p = data.draw(st.sampled_from(gf2.primitive_polynomials(n)))
    assert gf2.is_primitive(gf2.reciprocal(p))
    assert gf2.reciprocal(gf2.reciprocal(p)) == p
