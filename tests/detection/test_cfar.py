"""CA-CFAR: the threshold factor, the sliding threshold against a loop, P_FA and P_D against Monte Carlo.

Tolerances: a count k of n independent Bernoulli(p) trials is compared with n·p within 4 binomial standard
errors √(n p (1 − p)) (a 6·10⁻⁵ chance of a false failure per check). Independence: every row holds exactly one
cell under test with its own training cells, so the rows' decisions are independent.
"""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.cfar import CFARConfig, ca_cfar, ca_cfar_alpha, pd_swerling0, pd_swerling1


def _cn_power(rng, shape, power=1.0):
    """|w|² of circular complex Gaussian w of the given power (an Exp(power) sample), drawn from two normals."""
    w = rng.standard_normal((*shape, 2)) * math.sqrt(power / 2.0)
    return (w**2).sum(axis=-1)


def test_alpha_closed_form():
    # α = N (P^(−1/N) − 1); with N = 1: α = 1/P − 1
    assert ca_cfar_alpha(1e-3, 1) == pytest.approx(999.0)
    assert ca_cfar_alpha(1e-6, 32) == pytest.approx(32 * (1e-6 ** (-1 / 32) - 1), rel=1e-12)
    # large N: α → −ln P (the threshold of a known noise level)
    assert ca_cfar_alpha(1e-4, 4096) == pytest.approx(-math.log(1e-4), rel=2e-3)


@pytest.mark.parametrize("stride", [1, 3, 7])
def test_threshold_equals_a_loop(stride):
    rng = np.random.default_rng(5)
    cfg = CFARConfig(n_train=8, n_guard=2, pfa=1e-3, stride=stride)
    p = rng.exponential(size=(3, 150))
    ref = rng.exponential(size=(3, 150))
    for reference, scale in ((None, 1.0), (ref, 2.5)):
        det, thr = ca_cfar(p, cfg, reference=reference, scale=scale)
        src = p if reference is None else ref
        want = np.full(p.shape, np.inf)
        for n in range(p.shape[1]):
            cells = [n + sgn * (cfg.n_guard + j) * stride for sgn in (-1, 1) for j in range(1, 5)]
            if min(cells) >= 0 and max(cells) < p.shape[1]:
                want[:, n] = cfg.alpha * scale * src[:, cells].mean(axis=1)
        np.testing.assert_allclose(thr, want, rtol=1e-12)
        np.testing.assert_array_equal(det, p > want)


@pytest.mark.parametrize(("n_train", "stride", "pfa"), [(16, 1, 1e-3), (8, 4, 1e-2), (32, 2, 1e-2)])
def test_pfa_on_noise(n_train, stride, pfa):
    cfg = CFARConfig(n_train=n_train, n_guard=1, pfa=pfa, stride=stride)
    rows = 400_000 if pfa < 1e-2 else 100_000
    width = 2 * cfg.half_width + 1  # one valid CUT per row: its centre
    rng = np.random.default_rng(2008)
    p = _cn_power(rng, (rows, width), power=3.7)  # the noise power is unknown to the detector
    det, thr = ca_cfar(p, cfg)
    assert (
        np.isfinite(thr[:, cfg.half_width]).all() and np.isinf(np.delete(thr, cfg.half_width, axis=1)).all()
    )
    k = det[:, cfg.half_width].sum()
    se = math.sqrt(rows * pfa * (1 - pfa))
    assert abs(k - rows * pfa) < 4 * se, (k, rows * pfa, se)


def test_pfa_with_a_scaled_reference():
    # CUT power 8× the reference's (a coherent sum of 8 independent cells): scale = 8 keeps the P_FA
    cfg = CFARConfig(n_train=16, n_guard=0, pfa=1e-2)
    rows, width = 100_000, 2 * cfg.half_width + 1
    rng = np.random.default_rng(7)
    ref = _cn_power(rng, (rows, width))
    p = _cn_power(rng, (rows, width), power=8.0)
    det, _ = ca_cfar(p, cfg, reference=ref, scale=8.0)
    k = det[:, cfg.half_width].sum()
    assert abs(k - rows * 1e-2) < 4 * math.sqrt(rows * 1e-2 * 0.99)


@pytest.mark.parametrize("snr_db", [8.0, 11.0, 13.5])
def test_pd_nonfluctuating_against_monte_carlo(snr_db):
    s = 10 ** (snr_db / 10)
    cfg = CFARConfig(n_train=16, n_guard=0, pfa=1e-4)
    rows, width = 40_000, 2 * cfg.half_width + 1
    rng = np.random.default_rng(int(snr_db * 10))
    w = (rng.standard_normal((rows, width)) + 1j * rng.standard_normal((rows, width))) / math.sqrt(2)
    w[:, cfg.half_width] += math.sqrt(s) * np.exp(2j * math.pi * rng.random(rows))
    det, _ = ca_cfar(np.abs(w) ** 2, cfg)
    k = det[:, cfg.half_width].sum()
    pd = float(pd_swerling0(s, cfg.pfa, cfg.n_train))
    assert 0.05 < pd < 0.99
    assert abs(k - rows * pd) < 4 * math.sqrt(rows * pd * (1 - pd)), (k / rows, pd)


def test_pd_swerling1_against_monte_carlo():
    s = 10**1.5
    cfg = CFARConfig(n_train=16, n_guard=0, pfa=1e-4)
    rows, width = 40_000, 2 * cfg.half_width + 1
    rng = np.random.default_rng(3)
    p = _cn_power(rng, (rows, width))
    p[:, cfg.half_width] = _cn_power(rng, (rows,), power=1.0 + s)  # Rayleigh target + noise
    det, _ = ca_cfar(p, cfg)
    pd = float(pd_swerling1(s, cfg.pfa, cfg.n_train))
    k = det[:, cfg.half_width].sum()
    assert abs(k - rows * pd) < 4 * math.sqrt(rows * pd * (1 - pd))


def test_pd_limits():
    assert float(pd_swerling0(0.0, 1e-6, 32)) == pytest.approx(1e-6, rel=1e-6)
    assert float(pd_swerling1(0.0, 1e-6, 32)) == pytest.approx(1e-6, rel=1e-9)
    pd = pd_swerling0(np.array([1.0, 10.0, 100.0, 1000.0]), 1e-6, 32)
    assert np.all(np.diff(pd) > 0) and pd[-1] == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"n_train": 7}, "n_train"),
        ({"n_train": 0}, "n_train"),
        ({"pfa": 0.0}, "pfa"),
        ({"pfa": 0.9}, "pfa"),
        ({"stride": 0}, "stride"),
        ({"n_guard": -1}, "n_guard"),
    ],
)
def test_bad_config(kwargs, field):
    with pytest.raises(ConfigError) as exc:
        CFARConfig(**kwargs)
    assert exc.value.field == field
