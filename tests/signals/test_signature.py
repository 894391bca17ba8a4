"""Signature waveform of the mode-signature paper, eqs (1)–(3), and the checks of its configuration."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motionsig_cli.config import ConfigError
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes
from motionsig_cli.signals.signature import SignatureConfig, chip_index, mode_signature

CHIPS = to_bipolar(corrected_codes()[0])


def test_chip_index_definition():
    """j(k) = ⌊(k − τ)/m_ρ⌋ mod n_ρ, including negative k − τ."""
    k = np.arange(-50, 700)
    for tau in (-13, 0, 7, 45):
        expected = [math.floor((kk - tau) / 20) % 31 for kk in k]
        assert chip_index(k, tau, 20, 31).tolist() == expected


@settings(max_examples=30, deadline=None)
@given(
    theta=st.floats(-10, 10),
    tau=st.integers(-2000, 2000),
    m_rho=st.integers(1, 30),
    f_c=st.floats(0.0, 5.0),
)
def test_quadrature_identity(theta, tau, m_rho, f_c):
    """With f_d = 0: z = cos θ · z_cos − sin θ · z_sin, for any θ, τ, m_ρ, f_c."""
    sig = mode_signature(CHIPS, SignatureConfig(T=0.05, m_rho=m_rho, f_c=f_c, theta=theta, tau=tau), 400)
    np.testing.assert_allclose(sig.z, math.cos(theta) * sig.z_cos - math.sin(theta) * sig.z_sin, atol=1e-12)
    np.testing.assert_allclose(
        sig.zdot, math.cos(theta) * sig.zdot_cos - math.sin(theta) * sig.zdot_sin, atol=1e-9
    )


def test_code_phase_is_a_delay():
    """A code phase of τ samples delays the chip waveform by τ samples (period n_ρ m_ρ)."""
    base = mode_signature(CHIPS, SignatureConfig(tau=0), 620 * 2)
    shifted = mode_signature(CHIPS, SignatureConfig(tau=45), 620 * 2)
    assert np.array_equal(shifted.p, np.roll(base.p, 45))


def test_analytic_derivative_inside_chips():
    """Analytic ż against a central difference of z on a fine grid, away from chip edges: O(T²)."""
    cfg = SignatureConfig(T=1e-4, m_rho=10_000, f_c=1.0, theta=0.3)
    sig = mode_signature(CHIPS, cfg, 30_000)
    central = (sig.z[2:] - sig.z[:-2]) / (2 * cfg.T)
    interior = (sig.chip[2:] == sig.chip[:-2]) & (sig.chip[1:-1] == sig.chip[2:])
    err = np.max(np.abs(central - sig.zdot[1:-1])[interior])
    # central-difference error <= max|z'''| T^2/6 with |z'''| <= w^3 inside a chip (5 % slack for rounding)
    assert err < 1.05 * (2 * np.pi) ** 3 * cfg.T**2 / 6


def test_finite_difference_option():
    cfg = SignatureConfig(theta=0.7, tau=3)
    sig = mode_signature(CHIPS, cfg, 700, zdot="finite-difference")
    np.testing.assert_allclose(sig.zdot[1:], np.diff(sig.z) / cfg.T, atol=1e-12)


NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("T", 0.0),
        ("T", -1.0),
        ("T", NAN),
        ("T", INF),
        ("m_rho", 0),
        ("m_rho", 2.5),
        ("m_rho", True),
        ("f_c", -1.0),
        ("f_c", NAN),
        ("theta", INF),
        ("theta", NAN),
        ("tau", 1.5),
        ("tau", 2**53 + 1),
        ("tau", -(2**53) - 1),
        ("tau", NAN),
        ("tau", 10**20),
        ("f_d", INF),
        ("f_d", NAN),
    ],
)
def test_every_field_is_checked(field, value):
    with pytest.raises(ConfigError) as exc:
        SignatureConfig(**{field: value})
    assert exc.value.field == field


def test_wording_of_the_checks():
    """The sample interval must be positive; a code phase is bounded by 2^53 (exact as a float)."""
    with pytest.raises(ConfigError, match="positive"):
        SignatureConfig(T=0.0)
    with pytest.raises(ConfigError, match=r"2\^53"):
        SignatureConfig(tau=2**60)
    assert SignatureConfig(tau=2**53).tau == 2**53 and SignatureConfig(tau=-(2**53)).tau == -(2**53)


def test_non_bipolar_chips_rejected():
    with pytest.raises(ValueError, match="chips"):
        mode_signature(np.array([0, 1, 1]), SignatureConfig())
