"""The χ² validation gate of the local update (gate probability P_G): the threshold, the limit P_G → 1 for
every fusion rule, measurements beyond the gate ignored, and the likelihood-ratio identities
E[Λ | h0] = 1 and E[1/Λ | h1] = 1 that only the P_G-corrected ratio satisfies (Monte Carlo with clutter
and targets drawn here with numpy, 40 000 scans each; tolerance 4 standard errors)."""

import math

import numpy as np
import pytest
from scipy.stats import chi2

from motionsig_cli.detection.track_existence import FUSION_METHODS, FusionOptions, run_methods
from motionsig_cli.existence import slrt
from motionsig_cli.filters.pda import gate_threshold, local_update
from motionsig_cli.models.radar import MeasurementModel


@pytest.mark.parametrize("pg", [1e-6, 0.5, 0.9, 0.99, 0.999999, 1 - 1e-15])
def test_gate_threshold_is_the_chi2_2_quantile(pg):
    assert gate_threshold(pg) == pytest.approx(chi2.ppf(pg, 2), rel=1e-9)
    assert gate_threshold(1.0) == math.inf


def scenario_for(name, **kw):
    linear = dict(meas_model="cartesian", pd_true=1.0, pd_filter=1.0, clutter_rate=0.0)
    return slrt.SlrtScenario(**{**(linear if name == "dkf" else {}), **kw})


@pytest.mark.parametrize("name", list(FUSION_METHODS))
def test_a_gate_of_probability_one_is_no_gate_and_close_to_one_is_almost(name):
    """P_G = 1 gives the ungated scores to the last bit; P_G = 1 − 10⁻¹² to 10⁻⁹ relative (what is cut
    has a weight below e^{−27.6} relative to the prediction's, and 1 − p_D·P_G differs from 1 − p_D by
    10⁻¹²). The DKF refuses any gate below 1."""
    sc = scenario_for(name, n_sensors=3, scans=12, clutter_rate=8.0 if name != "dkf" else 0.0)
    gen = slrt.generate(sc, range(5), 31)
    model = sc.model()
    plain = run_methods(model, gen.m0, gen.scans, [name])[name]
    one = run_methods(model, gen.m0, gen.scans, [name], options=FusionOptions(gate_pg=1.0))[name]
    np.testing.assert_array_equal(one, plain)
    if name != "dkf":
        near = run_methods(model, gen.m0, gen.scans, [name], options=FusionOptions(gate_pg=1 - 1e-12))[name]
        np.testing.assert_allclose(near, plain, rtol=1e-9, atol=1e-7)
        tight = run_methods(model, gen.m0, gen.scans, [name], options=FusionOptions(gate_pg=0.9))[name]
        assert np.abs(tight - plain).max() > 1e-3  # the gate does act


def one_filter(gate_pg, z):
    """One Cartesian filter at the origin (S = diag(150² + 50²) per axis) updated with measurements z."""
    meas = MeasurementModel("cartesian", np.diag([50.0**2, 50.0**2]), fov_range=1000.0)
    m = np.zeros((1, 4))
    P = np.diag([150.0**2, 10.0**2, 150.0**2, 10.0**2])[None]
    Z = np.asarray(z, dtype=float).reshape(1, -1, 2)
    return local_update(
        m, P, Z, np.ones(Z.shape[:2], bool), np.zeros(2), meas, 0.9, math.log(5e-6), gate_pg=gate_pg
    )


def test_measurements_beyond_the_gate_are_ignored_and_those_inside_count():
    """d² = (r/158.1)²: with P_G = 0.99 (γ = 9.21, radius 479.9 m) a measurement at 500 m changes nothing,
    one at 460 m changes the update; the missed term is log(1 − 0.9·0.99)."""
    base = one_filter(0.99, [[100.0, -50.0]])
    beyond = one_filter(0.99, [[100.0, -50.0], [500.0, 0.0]])
    inside = one_filter(0.99, [[100.0, -50.0], [0.0, 460.0]])
    for a, b in zip(base, beyond, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-15, atol=0)
    assert abs(inside[2][0] - base[2][0]) > 1e-4
    empty = one_filter(0.99, np.zeros((0, 2)))
    assert empty[2][0] == pytest.approx(math.log1p(-0.9 * 0.99), rel=1e-15)
    assert one_filter(None, np.zeros((0, 2)))[2][0] == pytest.approx(math.log1p(-0.9), rel=1e-15)


def draw_scans(rng, n, target, pd=0.9, rate=20.0):
    """n independent scans of one Cartesian sensor (FoV: the square of half-width 1000 m; Poisson clutter,
    rate 20, so ρ_F = 20/4·10⁶ = 5·10⁻⁶ /m²) and, with a target, a detection (p_D) at z = Hx + v with x
    drawn from the filter's prior (so that its measurement law is N(0, S)), padded to a common length."""
    counts = rng.poisson(rate, n)
    det = target & (rng.random(n) < pd)
    sizes = counts + det
    V = np.arange(sizes.max())[None, :] < sizes[:, None]
    Z = np.zeros((*V.shape, 2))
    Z[V] = rng.uniform(-1000.0, 1000.0, (int(sizes.sum()), 2))
    x = rng.normal(0.0, 150.0, (n, 2)) + rng.normal(0.0, 50.0, (n, 2))  # the target's measurement
    Z[det, 0] = x[det]
    return Z, V


def scan_ratio(Z, V, gate_pg):
    n = Z.shape[0]
    meas = MeasurementModel("cartesian", np.diag([50.0**2, 50.0**2]), fov_range=1000.0)
    m = np.zeros((n, 4))
    P = np.broadcast_to(np.diag([150.0**2, 10.0**2, 150.0**2, 10.0**2]), (n, 4, 4))
    return np.exp(local_update(m, P, Z, V, np.zeros(2), meas, 0.9, math.log(5e-6), gate_pg=gate_pg)[2])


@pytest.mark.parametrize("pg", [0.9, 0.6])
def test_the_gated_ratio_is_a_likelihood_ratio(pg):
    """E[Λ | h0] = 1 and E[1/Λ | h1] = 1 hold for a likelihood ratio of the gated data; the gate (radius
    ≤ 340 m) lies inside the field of view. A missed-detection term of 1 − p_D (not 1 − p_D·P_G) would
    shift E[Λ | h0] by p_D(1 − P_G) ≥ 0.09, more than 10 standard errors here."""
    rng = np.random.default_rng(int(pg * 100))
    n = 40_000
    lam0 = scan_ratio(*draw_scans(rng, n, False), pg)
    inv1 = 1.0 / scan_ratio(*draw_scans(rng, n, True), pg)
    for x in (lam0, inv1):
        se = x.std(ddof=1) / math.sqrt(n)
        assert abs(x.mean() - 1.0) < 4 * se, (x.mean(), se)
        assert 0.9 * (1 - pg) > 10 * se
