"""Motion models of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*: each matrix checked against an independent derivation."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.models.motion import ModelSet, cv_input_model, imm_models, two_point_init


@pytest.mark.parametrize("T", [1.0, 0.5, 2.0])
def test_input_model_is_exact_constant_acceleration_kinematics(T):
    """F x + G u = (p + vT + ½uT², v + uT) per axis: the exact kinematics of a held acceleration."""
    F, G, Q = cv_input_model(T, 3.0)
    rng = np.random.default_rng(1)
    x, u = rng.normal(size=4) * 100, rng.normal(size=2) * 10
    got = F @ x + G @ u
    p, v = x[[0, 2]], x[[1, 3]]
    np.testing.assert_allclose(got[[0, 2]], p + v * T + 0.5 * u * T * T, rtol=1e-14)
    np.testing.assert_allclose(got[[1, 3]], v + u * T, rtol=1e-14)
    # continuous white-noise acceleration: Q = q ∫₀ᵀ [t, 1]ᵀ[t, 1] dt per axis
    np.testing.assert_allclose(Q[:2, :2], 3.0 * np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]]))
    assert np.all(Q[:2, 2:] == 0)


@pytest.mark.parametrize("T", [1.0, 0.25])
def test_g2_paper_fixed_is_the_trapezoidal_model_on_both_axes(T):
    """The corrected G₂: X⁺ = Φ₂X + G₂w equals p⁺ = p + vT + (T²/2)(a + a⁺)/2, v⁺ = v + T(a + a⁺)/2,
    a⁺ = a + w on x *and* y (the paper prints T instead of T/2 in the ẏ row)."""
    ms = imm_models(T)
    G2 = np.array([[T * T / 4, 0], [T / 2, 0], [0, T * T / 4], [0, T / 2], [1, 0], [0, 1]])
    Qd_expected = 0.001 * G2 @ G2.T  # Q₂ = 0.001 I (paper §IV)
    np.testing.assert_allclose(ms.Qd[1], Qd_expected, rtol=1e-14)
    rng = np.random.default_rng(2)
    X, w = rng.normal(size=6), rng.normal(size=2)
    got = ms.Phi[1] @ X + G2 @ w
    a, v, p = X[[4, 5]], X[[1, 3]], X[[0, 2]]
    a1 = a + w
    np.testing.assert_allclose(got[[0, 2]], p + v * T + T * T / 2 * (a + a1) / 2, rtol=1e-13)
    np.testing.assert_allclose(got[[1, 3]], v + T * (a + a1) / 2, rtol=1e-13)
    np.testing.assert_allclose(got[[4, 5]], a1, rtol=1e-14)
    # the printed ẏ entry T would break the x/y symmetry
    printed = G2.copy()
    printed[3, 1] = T
    assert not np.allclose(0.001 * printed @ printed.T, ms.Qd[1])
    std = imm_models(T, g2="standard")
    Gs = np.array([[T * T / 2, 0], [T, 0], [0, T * T / 2], [0, T], [1, 0], [0, 1]])
    np.testing.assert_allclose(std.Qd[2], 0.0144 * Gs @ Gs.T, rtol=1e-14)  # Q₃ = 0.0144 I (paper §IV)


def test_model_one_forces_zero_acceleration_and_has_no_noise():
    ms = imm_models(1.0)
    X = np.arange(1.0, 7.0)
    out = ms.Phi[0] @ X
    assert out[4] == out[5] == 0.0
    np.testing.assert_allclose(out[:4], [1 + 2, 2, 3 + 4, 4])
    assert np.all(ms.Qd[0] == 0)


def test_two_point_init():
    x, P = two_point_init(np.array([10.0, 20.0]), np.array([13.0, 18.0]), 2.0, 5.0)
    np.testing.assert_allclose(x, [13.0, 1.5, 18.0, -1.0, 0.0, 0.0])
    block = np.array([[25.0, 12.5], [12.5, 12.5]])
    np.testing.assert_allclose(P[:2, :2], block)
    np.testing.assert_allclose(P[2:4, 2:4], block)  # δ_y in the ẏ entry (the printed δ_x corrected)
    assert np.all(P[4:] == 0) and np.all(P[:, 4:] == 0) and np.all(P[:2, 2:] == 0)
    x4, P4 = two_point_init(np.zeros((3, 2)), np.ones((3, 2)), 1.0, 1.0, n=4)
    assert x4.shape == (3, 4) and P4.shape == (4, 4)


@pytest.mark.parametrize(
    ("Pi", "mu0", "field", "match"),
    [
        ([[0.9, 0.2, 0.0], [0, 1, 0], [0, 0, 1]], [1, 0, 0], "Pi", "row 1"),
        ([[1.1, -0.1, 0.0], [0, 1, 0], [0, 0, 1]], [1, 0, 0], "Pi", "row 1"),
        ([[1, 0, 0], [0, 1, 0], [0, 0.5, 0.4]], [1, 0, 0], "Pi", "row 3"),
        ([[1, 0], [0, 1]], [1, 0, 0], "Pi", "3 rows of 3"),
        ([[1, 0, 0], [0, 1, 0], [0, 0, np.nan]], [1, 0, 0], "Pi", "row 3"),
        ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.8, 0.1, 0.2], "mu0", "probability vector"),
        ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [1.2, -0.1, -0.1], "mu0", "probability vector"),
        ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [1.0, 0.0], "mu0", "3 probabilities"),
    ],
)
def test_model_set_refuses_bad_probabilities(Pi, mu0, field, match):
    with pytest.raises(ConfigError, match=match) as info:
        imm_models(1.0, Pi=np.array(Pi, float), mu0=np.array(mu0, float))
    assert info.value.field == field


def test_model_set_refuses_indefinite_noise_and_bad_shapes():
    ms = imm_models(1.0)
    Qd = ms.Qd.copy()
    Qd[1, 0, 0] = -1.0
    for kw, field in (
        ({"Qd": Qd}, "Qd"),
        ({"Qd": ms.Qd[:2]}, "Qd"),
        ({"Phi": ms.Phi[:, :5]}, "Phi"),
        ({"Phi": np.full_like(ms.Phi, np.inf)}, "Phi"),
        ({"names": ("a", "b")}, "names"),
    ):
        args = {"Phi": ms.Phi, "Qd": ms.Qd, "Pi": ms.Pi, "mu0": ms.mu0} | kw
        with pytest.raises(ConfigError) as info:
            ModelSet(**args)
        assert info.value.field == field


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: cv_input_model(0.0, 1.0), "T"),
        (lambda: cv_input_model(1.0, -1.0), "q0"),
        (lambda: cv_input_model(1.0, 2e6), "q0"),
        (lambda: imm_models(math.nan), "T"),
        (lambda: imm_models(1.0, g2="printed"), "g2"),
        (lambda: imm_models(1.0, q=(0.0, -1.0, 0.0)), "q"),
        (lambda: two_point_init(np.zeros(2), np.zeros(2), 1.0, 1.0, n=5), "n"),
    ],
)
def test_model_functions_refuse_bad_arguments_by_name(call, field):
    with pytest.raises(ConfigError) as info:
        call()
    assert info.value.field == field
