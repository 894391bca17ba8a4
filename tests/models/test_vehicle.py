"""1-D closed loop of the mode-signature paper (eqs 53–55), the pole-placement gain, the ANR → R conversion
(eq 58) and the checks of the vehicle's configuration."""

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.models.vehicle import (
    Vehicle1D,
    measurement_variance,
    pole_placement_gain,
    simulate_1d,
    transition_h0,
)


def test_pole_placement_matches_spec_and_places_poles():
    """T = 0.05 → K ≈ [101.66, 16.78]; the closed-loop eigenvalues are e^{sT}."""
    k1, k2 = pole_placement_gain(0.05)
    assert abs(k1 - 101.66) < 5e-3 and abs(k2 - 16.78) < 5e-3
    wn, zeta, T = 4 * np.pi, 0.7, 0.05
    s = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    eig = np.linalg.eigvals(np.array([[1, T], [-T * k1, 1 - T * k2]]))
    np.testing.assert_allclose(
        sorted(eig, key=np.imag), sorted([np.exp(s * T), np.exp(np.conj(s) * T)], key=np.imag), atol=1e-12
    )


def test_simulation_follows_equations_step_by_step():
    """Every sample obeys x_{k+1} = A x_k + B u_k + G w_k, u_k = K(−x_k + r_k + a[z_k, ż_k]), y_k = x_k + v_k."""
    rng = np.random.default_rng(3)
    cfg = Vehicle1D(R=1e-3, f_r=0.1)
    N = 50
    z, zd, w, v = (rng.standard_normal((2, N)) for _ in range(4))
    sim = simulate_1d(cfg, z, zd, w, v)
    T, (k1, k2) = cfg.T, cfg.K
    r = sim["r"]
    for b in range(2):
        x = sim["x"][b]
        for k in range(N - 1):
            u = k1 * (-x[k, 0] + r[k, 0] + cfg.a_sig * z[b, k]) + k2 * (
                -x[k, 1] + r[k, 1] + cfg.a_sig * zd[b, k]
            )
            assert np.isclose(sim["u"][b, k], u)
            acc = cfg.sigma_a * w[b, k]
            np.testing.assert_allclose(
                x[k + 1], [x[k, 0] + T * x[k, 1] + T**2 / 2 * acc, x[k, 1] + T * u + T * acc]
            )
        np.testing.assert_allclose(sim["y"][b], x[:, 0] + np.sqrt(cfg.R) * v[b])


def test_noise_free_tracking_of_slow_reference():
    """Without noise and signature the loop tracks the 0.01 Hz reference (type-1 loop with velocity feed-forward)."""
    cfg = Vehicle1D(sigma_a=0.0, f_r=0.01)
    N = 1600
    zeros = np.zeros((1, N))
    sim = simulate_1d(cfg, zeros, zeros, zeros, zeros)
    err = np.abs(sim["x"][0, 200:, 0] - sim["r"][200:, 0])
    assert err.max() < 1e-2 * cfg.a_r


def test_h0_transition_is_upper_block_of_eq44():
    cfg = Vehicle1D()
    F = transition_h0(cfg)
    k1, k2 = cfg.K
    np.testing.assert_allclose(F[1], [-cfg.T * k1, 1 - cfg.T * k2, cfg.T * k1, cfg.T * k2])
    assert F[2, 3] == cfg.T and transition_h0(cfg, "identity")[2, 3] == 0


NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("T", 0.0),
        ("T", -0.05),
        ("T", NAN),
        ("T", INF),
        ("K", (1.0,)),
        ("K", (1.0, 2.0, 3.0)),
        ("K", (1.0, NAN)),
        ("K", (INF, 1.0)),
        ("K", "ab"),
        ("K", None),
        ("a_sig", -0.5),
        ("a_sig", NAN),
        ("a_r", -1.0),
        ("a_r", INF),
        ("f_r", -0.01),
        ("f_r", NAN),
        ("sigma_a", -1.0),
        ("sigma_a", INF),
        ("R", 0.0),
        ("R", -1e-3),
        ("R", INF),
        ("R", NAN),
    ],
)
def test_every_field_is_checked(field, value):
    with pytest.raises(ConfigError) as exc:
        Vehicle1D(**{field: value})
    assert exc.value.field == field


@pytest.mark.parametrize("field", ["a_sig", "a_r", "f_r", "sigma_a"])
def test_zero_amplitudes_and_noise_are_allowed(field):
    assert getattr(Vehicle1D(**{field: 0.0}), field) == 0.0


@pytest.mark.parametrize(
    ("args", "field"),
    [
        ((0.0,), "T"),
        ((-0.05,), "T"),
        ((1e-300,), "T"),  # T² underflows
        ((0.05, 0.0), "wn"),
        ((0.05, NAN), "wn"),
        ((0.05, 4.0, 0.0), "zeta"),
        ((0.05, 4.0, 1.0), "zeta"),
        ((0.05, 4.0, -0.1), "zeta"),
    ],
)
def test_pole_placement_checks_its_arguments(args, field):
    with pytest.raises(ConfigError) as exc:
        pole_placement_gain(*args)
    assert exc.value.field == field


def test_measurement_variance_from_R_or_an_anr():
    """ANR = a²/(2R) (eq 58), in true decibels by default: 94.3 dB is R ≈ 4.6e-11; the paper's 10·ln label
    94.335 is R ≈ 1e-5."""
    assert measurement_variance(None, None) == 1e-5
    assert measurement_variance(2e-3, None) == 2e-3
    assert measurement_variance(None, 94.3) == pytest.approx(4.6e-11, rel=2e-2)
    assert measurement_variance(None, 94.3, "log10") == measurement_variance(None, 94.3)
    assert measurement_variance(None, 94.335, "paper-ln") == pytest.approx(1e-5, rel=1e-3)
    R = measurement_variance(None, 20.0, a_sig=2.0)
    assert 10 * math.log10(2.0**2 / (2 * R)) == pytest.approx(20.0)


@pytest.mark.parametrize("a_sig", [0.5, 2.0])
def test_anr_db_is_true_decibels_by_default(a_sig):
    """21 dB is ANR = 10^2.1 (to rounding): R = a²/(2·10^2.1); 21 paper dB is ANR = e^2.1."""
    with localcontext() as ctx:  # 10^2.1 and e^2.1 to 40 digits, independently of the float code under test
        ctx.prec = 40
        true_anr = float(Decimal(10) ** Decimal("2.1"))  # 125.892541179416721...
        paper_anr = float(Decimal("2.1").exp())  # 8.16616991256765007...
    assert math.isclose(
        measurement_variance(None, 21.0, a_sig=a_sig), a_sig**2 / (2 * true_anr), rel_tol=1e-12
    )
    got = measurement_variance(None, 21.0, "paper-ln", a_sig=a_sig)
    assert math.isclose(got, a_sig**2 / (2 * paper_anr), rel_tol=1e-12)


def test_paper_labels_with_paper_ln():
    """The paper's labels of Figs 4–6 (10·ln of ANR = 0.125/R at a_sig = 0.5) with ``paper-ln``: 48.3 is
    R = 0.125·e^(-4.83) = 9.98e-4 ≈ 1e-3 and 94.3 is 1.0035e-5 ≈ 1e-5 (the labels are rounded to 0.1)."""
    R = measurement_variance(None, 48.3, "paper-ln")
    assert math.isclose(R, 0.125 * math.exp(-4.83), rel_tol=1e-12)
    assert R == pytest.approx(1e-3, rel=2e-3)  # the label is 10·ln(125) = 48.283 rounded: 0.17 % off
    assert measurement_variance(None, 94.3, "paper-ln") == pytest.approx(1e-5, rel=4e-3)
    assert measurement_variance(None, 48.3) == pytest.approx(0.125 * 10**-4.83, rel=1e-12)  # not 1e-3


@pytest.mark.parametrize(
    ("args", "field"),
    [
        ((1e-3, 40.0), "anr_db"),  # both given
        ((None, NAN), "anr_db"),
        ((None, 1e6), "anr_db"),  # R underflows
        ((None, -1e6), "anr_db"),  # R overflows
        ((None, 40.0, "dB"), "db_convention"),
        ((None, 40.0, "paper-ln", 0.0), "a_sig"),  # no R gives an ANR without a signature
    ],
)
def test_measurement_variance_refuses(args, field):
    with pytest.raises(ConfigError) as exc:
        measurement_variance(*args)
    assert exc.value.field == field
