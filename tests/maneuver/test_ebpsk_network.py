"""The multi-node EBPSK location (motionsig_cli.maneuver.ebpsk_network).

Oracles: the GDOP of n nodes equally spaced in bearing is 2/√n (Σ u uᵀ = (n/2) I, derived in the module
docstring, eq. W4); the WLS covariance is checked against the Monte Carlo scatter of the estimates (whitened
errors of unit covariance within 4 SE, SE of a sample second moment √(2/n)); the fix rate of the network
against the Poisson-binomial probability computed node by node.
"""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.maneuver import ebpsk_tracking as et
from motionsig_cli.maneuver.ebpsk_network import (
    DEFAULT_NODES,
    NodeNetwork,
    gdop,
    multilaterate,
    network_table,
)
from motionsig_cli.maneuver.scenario import ManeuverScenario


def ring(n, radius=100e3, centre=(20e3, -5e3), phase=0.3):
    a = phase + 2 * math.pi * np.arange(n) / n
    return np.asarray(centre) + radius * np.stack([np.cos(a), np.sin(a)], axis=-1)


@pytest.mark.parametrize("n", [3, 4, 7])
def test_gdop_of_a_symmetric_ring_is_its_closed_form(n):
    nodes = ring(n)
    target = np.array([20e3, -5e3])
    assert gdop(nodes, target) == pytest.approx(2 / math.sqrt(n), rel=1e-12)
    # the WLS covariance at the truth, equal σ: σ² (2/n) I
    r = np.linalg.norm(target - nodes, axis=1)
    _, cov = multilaterate(r, 3.0, nodes)
    np.testing.assert_allclose(cov, 9.0 * 2 / n * np.eye(2), rtol=1e-9, atol=1e-9)


def test_noiseless_ranges_give_the_position_from_the_closed_form_start():
    """Eq. W1 is exact without noise: zero Gauss–Newton steps already give the position (any geometry)."""
    rng = np.random.default_rng(5)
    nodes = rng.uniform(-200e3, 200e3, (5, 2))
    p = rng.uniform(-300e3, 300e3, (50, 2))
    r = np.linalg.norm(p[:, None, :] - nodes, axis=-1)
    for it in (0, 5):
        xy, _ = multilaterate(r, 1.0, nodes, iterations=it)
        np.testing.assert_allclose(xy, p, atol=1e-4)


def test_wls_covariance_matches_the_monte_carlo_scatter():
    """4 nodes, unequal σ, 20 000 noisy range sets: the whitened errors L⁻¹(p̂ − p) have mean 0 and unit
    covariance within 4 SE (the linearisation is exact to ~σ/r ≈ 10⁻⁴ here)."""
    nodes = np.array([[0.0, 0.0], [150e3, 20e3], [60e3, 180e3], [-40e3, 90e3]])
    sig = np.array([3.0, 8.0, 5.0, 12.0])
    p = np.array([50e3, 70e3])
    n = 20_000
    g = np.random.default_rng(12)
    r = np.linalg.norm(p - nodes, axis=1) + sig * g.standard_normal((n, 4))
    xy, cov = multilaterate(r, sig, nodes)
    w = np.linalg.solve(np.linalg.cholesky(cov), (xy - p)[..., None])[..., 0]
    assert np.all(np.abs(w.mean(axis=0)) < 4 / math.sqrt(n))
    np.testing.assert_allclose(w.T @ w / n, np.eye(2), atol=4 * math.sqrt(2 / n))


def test_missing_nodes_get_no_weight():
    nodes = ring(5)
    p = np.array([0.0, 10e3])
    g = np.random.default_rng(1)
    r = np.linalg.norm(p - nodes, axis=1) + 2.0 * g.standard_normal(5)
    sig = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    r_nan = r.copy()
    r_nan[[1, 3]] = np.nan
    xy, cov = multilaterate(r_nan, sig, nodes)
    keep = [0, 2, 4]
    xy3, cov3 = multilaterate(r[keep], sig[keep], nodes[keep])
    np.testing.assert_allclose(xy, xy3, atol=1e-6)
    np.testing.assert_allclose(cov, cov3, rtol=1e-9)
    r_nan[0] = np.nan  # two left: no position
    xy, cov = multilaterate(r_nan, sig, nodes)
    assert np.all(np.isnan(xy)) and np.all(np.isnan(cov))


@pytest.mark.parametrize(
    "kw, field",
    [
        ({"nodes": [[0.0, 0.0]]}, "nodes"),
        ({"nodes": [[0.0, 0.0], [0.0, 0.0], [1.0, 1.0]]}, "nodes"),
        ({"nodes": [[0.0, math.nan], [1.0, 0.0], [2.0, 2.0]]}, "nodes"),
        ({"sigmas": 0.0}, "sigmas"),
        ({"ranges": np.ones(2)}, "ranges"),
        ({"iterations": -1}, "iterations"),
    ],
)
def test_multilaterate_errors_name_the_argument(kw, field):
    args = {"ranges": np.ones(3), "sigmas": 1.0, "nodes": ring(3), **kw}
    with pytest.raises(ConfigError) as e:
        multilaterate(args.pop("ranges"), args.pop("sigmas"), args.pop("nodes"), **args)
    assert e.value.field == field


@pytest.fixture(scope="module")
def network():
    sc = ManeuverScenario("literal")
    fe = et.EbpskFrontEnd().prepared(sc.truth()).calibrated(sc.truth(), 100.0)
    return sc, NodeNetwork(fe)


def test_network_fix_rate_and_accuracy_along_the_track(network):
    """Along the literal track at the power that gives the single radar a median σ of 100 m: the fix rate
    of the Monte Carlo is the Poisson-binomial probability within 4 SE; the RMS error is never below the
    all-nodes bound by more than 4 SE, and is far below the single radar's σ and the paper's 100 m."""
    sc, net = network
    tab = network_table(sc, net, runs=60, seed=3)
    c = tab.columns
    n_scans = {r[0]: r[2] - r[1] + 1 for r in tab.rows}
    for row in tab.rows:
        n = 60 * n_scans[row[0]]
        p = row[c.index("fix_probability")]
        assert abs(row[c.index("fix_rate")] - p) <= 4 * math.sqrt(p * (1 - p) / n) + 1e-12
        rms, se, bound = (row[c.index(k)] for k in ("rms_pos_m", "rms_pos_se_m", "bound_pos_m"))
        assert rms >= bound - 4 * se
        assert rms < 1.0 < row[c.index("single_median_sigma_pos_m")]
    track = tab.rows[-1]
    assert track[0] == "track" and track[c.index("single_median_sigma_pos_m")] == pytest.approx(100.0)
    assert tab.meta["network"]["nodes_m"] == [list(p) for p in DEFAULT_NODES]


def test_network_measure_streams_are_per_run(network):
    sc, net = network
    truth = sc.truth()[:40]
    rngs = [np.random.default_rng(c) for c in np.random.SeedSequence(8).spawn(3)]
    xy, _ = net.measure(truth, rngs)
    again = [np.random.default_rng(c) for c in np.random.SeedSequence(8).spawn(3)]
    xy1, _ = net.measure(truth, again[1:2])
    np.testing.assert_array_equal(xy[1:2], xy1)


@pytest.mark.parametrize(
    "kw, field",
    [({"min_nodes": 2}, "min_nodes"), ({"min_nodes": 8}, "min_nodes"), ({"nodes": ((0.0, 0.0),)}, "nodes")],
)
def test_network_config_errors(network, kw, field):
    with pytest.raises(ConfigError) as e:
        NodeNetwork(network[1].front_end, **kw)
    assert e.value.field == field
