"""The 2-D radar vehicle of the mode-signature paper (eqs 59–62) against the independent oracle in
tests/filters/ukf_oracle.py and the paper's printed ANR labels; the checks of its configuration."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.models import vehicle2d as V
from tests.filters import ukf_oracle as O


def test_simulation_equals_oracle():
    rng = np.random.default_rng(11)
    N = 300
    z = rng.choice([-1.0, 1.0], size=N) * np.cos(np.arange(N) * 0.3)
    zd = rng.normal(size=N)
    w, v = rng.normal(size=(N, 2)), rng.normal(size=(N, 2))
    for axes, amps in (("both", (0.5, 0.5)), ("x", (0.5, 0.0)), ("y", (0.0, 0.5))):
        veh = V.Vehicle2D(f_r=0.1, sigma_a=0.3, R_range=1e-2, R_bearing=1e-3, sig_axes=axes)
        sim = V.simulate_2d(veh, z[None], zd[None], w[None], v[None])
        X, Y = O.simulate_2d(
            veh.T,
            *veh.K,
            *amps,
            veh.a_r,
            veh.f_r,
            veh.sigma_a,
            veh.R_range,
            veh.R_bearing,
            veh.start,
            z,
            zd,
            w,
            v,
        )
        assert veh.amplitudes == amps
        assert np.allclose(sim["x"][0], X, rtol=0, atol=1e-10)
        assert np.allclose(sim["y"][0], Y, rtol=0, atol=1e-10)
    assert np.all(np.abs(sim["y"][0, :, 1]) <= math.pi)


@pytest.mark.parametrize("g", [None, (0.7, -0.2)])
def test_filter_transitions_equal_oracle(g):
    T, K = 0.05, (101.66, 16.78)
    if g is None:
        F = V.transition_h0_2d(T, K)
    else:
        F = V.transition_h1_2d_base(T, K)
        for (i, j), gv in zip(V.AMPLITUDE_ENTRIES_2D, g, strict=True):
            F[i, j] = gv
    assert np.array_equal(F, O.transition_2d(T, *K, g))
    assert F.shape == ((8, 8) if g is None else (10, 10))
    assert len(V.Q0_2D) == 8 and len(V.Q1_2D) == 10  # eqs 61, 62


def test_anr_pairs_reproduce_the_seed_labels():
    """10·ln(0.125/R_χ) = 9.16, 32.19, 55.21, 101.27 (labels 9.2 … 101.3); R_κ from the range labels."""
    expected_rk = (3.06e-3, 3.04e-4, 3.05e-5, 3.06e-7)
    for pair, ((ang, rng_label), rk) in enumerate(zip(V.SEED_ANR_PAIRS, expected_rk, strict=True), start=1):
        R_range, R_bearing = V.anr_pair_variances(pair)
        assert round(10 * math.log(0.125 / R_bearing), 1) == pytest.approx(ang, abs=0.051)
        assert 10 * math.log(0.125 / R_range) == pytest.approx(rng_label, abs=1e-9)
        assert R_range == pytest.approx(rk, rel=0.01)
        assert R_bearing / R_range == pytest.approx(16.3, rel=0.02)  # "R_κ ≈ R_χ/16.3"
    with pytest.raises(ValueError):
        V.anr_pair_variances(5)


def test_range_bearing_axis_and_validation():
    p = np.array([[3.0, 9.0, 4.0], [-1.0, 0.0, 0.0]])
    assert np.allclose(V.range_bearing(p), [[5.0, math.atan2(4, 3)], [1.0, math.pi]])
    assert np.allclose(V.range_bearing(p.T, axis=0), V.range_bearing(p).T)
    with pytest.raises(ValueError, match="origin"):
        V.Vehicle2D(start=(0.0, 0.0))
    with pytest.raises(ValueError, match="R_range"):
        V.Vehicle2D(R_range=0.0)


NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("T", 0.0),
        ("T", NAN),
        ("K", (1.0,)),
        ("K", (1.0, INF)),
        ("a_sig", -0.5),
        ("a_r", NAN),
        ("f_r", -1.0),
        ("sigma_a", INF),
        ("R_range", 0.0),
        ("R_range", NAN),
        ("R_bearing", -1e-3),
        ("R_bearing", INF),
        ("start", (1.0, 2.0, 3.0)),
        ("start", (1.0, NAN)),
        ("start", ("a", "b")),
        ("start", (0.0, 0.0)),
        ("sig_axes", "z"),
        ("sig_axes", "X"),
    ],
)
def test_every_field_is_checked(field, value):
    with pytest.raises(ConfigError) as exc:
        V.Vehicle2D(**{field: value})
    assert exc.value.field == field


@pytest.mark.parametrize(
    ("args", "field"), [((0,), "anr_pair"), ((5,), "anr_pair"), ((2.5,), "anr_pair"), ((1, 0.0), "a_sig")]
)
def test_anr_pair_variances_refuse(args, field):
    with pytest.raises(ConfigError) as exc:
        V.anr_pair_variances(*args)
    assert exc.value.field == field


def test_radar_noise_from_a_pair_or_the_variances():
    p2, p4 = V.anr_pair_variances(2), V.anr_pair_variances(4)
    assert V.radar_noise(None, None, None) == (*p4, 4)  # default: the best pair, reported
    assert V.radar_noise(2, None, None) == (*p2, 2)
    assert V.radar_noise(None, 1e-3, 2e-3) == (1e-3, 2e-3, None)
    assert V.radar_noise(None, 1e-3, None) == (1e-3, p4[1], None)  # one variance given: no pair reported
    assert V.radar_noise(None, None, 2e-3) == (p4[0], 2e-3, None)
    assert V.radar_noise(3, None, None, a_sig=1.0) == (*V.anr_pair_variances(3, 1.0), 3)


@pytest.mark.parametrize(
    ("args", "field"),
    [
        ((2, 1e-3, None), "anr_pair"),
        ((2, None, 1e-3), "anr_pair"),
        ((7, None, None), "anr_pair"),
        ((None, None, None, 0.0), "a_sig"),
    ],
)
def test_radar_noise_refuses(args, field):
    with pytest.raises(ConfigError) as exc:
        V.radar_noise(*args)
    assert exc.value.field == field
