"""Multiple-access noise and the ROC (ATC-10 §3): the density registry, densities, bounds, exact ROC,
Gaussian comparison, exponents, time–bandwidth.

Oracles: ``tests/surveillance/mac_oracle.py`` (an independent mpmath implementation written from the
report's equations: quadrature MGFs, numerical derivatives, bisection, Irwin–Hall alternating sums at
≥ 90 digits, an RF-level matched-filter simulation), and reference values T1 … T12 computed by a third
implementation (the report prints no numbers for Figs 3.3–3.10, only the Reference [1] example, checked
in the CLI tests).
"""

import math

import numpy as np
import pytest

from motionsig_cli.atc10.mac_roc import (
    DENSITY_OF_FIGURE,
    REPORT_N,
    REPORT_TAU_OVER_ALPHA,
    figure_command,
    pf_at_pm,
    report_model,
)
from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance.amplitude import Discrete, Laplace, TwoPoint, Uniform, b_of_ell, ell_of_b
from motionsig_cli.surveillance.densities import DENSITIES as REGISTRY
from motionsig_cli.surveillance.densities import density, density_kind, kind_of
from motionsig_cli.surveillance.gaussian_roc import gaussian_power, gaussian_roc
from motionsig_cli.surveillance.multiple_access import MANModel
from motionsig_cli.surveillance.psk_amplitude import PSKAmplitude, chip_correlation
from motionsig_cli.surveillance.quasi_optimal import (
    exp_of_gaussian_exponent,
    exp_of_gaussian_exponent_exact,
    quasi_optimal_exponent,
    quasi_optimal_exponent_approx,
)
from motionsig_cli.surveillance.roc_bounds import chernoff, roc_bounds, theta_for_pd
from motionsig_cli.surveillance.roc_exact import exact_roc
from motionsig_cli.surveillance.time_bandwidth import (
    BARKER13,
    MSEQ31,
    b_from_autocorrelations,
    b_random_codes,
    psk_power,
    reference1_power,
    zakai_bandwidth,
    zakai_bandwidth_report,
)
from tests.surveillance import mac_oracle as oracle

DENSITIES = tuple(k.name for k in REGISTRY.values() if k.exact_roc)  # two-point … laplace
SCALAR = [k.name for k in REGISTRY.values() if not k.chip_level]  # the exact ones and arcsine
N, TA = REPORT_N, REPORT_TAU_OVER_ALPHA  # ATC-10 §3.6: N = 1e5, τ/α = 2e-5


def rel(a, b):
    return abs(a - b) / abs(b)


# --- densities ------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", SCALAR)
def test_cgf_matches_quadrature_and_derivatives(name):
    """g = ln Φ against the oracle's quadrature of e^{ρx}C(x); g′, g″ against central differences."""
    b = 0.01
    d = density(name, b)
    assert d.b == pytest.approx(b, rel=1e-14)
    rs = np.array([1e-4, 0.3, 3.0, 12.0]) / math.sqrt(b)
    if name == "laplace":
        rs = rs[rs * math.sqrt(b / 2) < 0.9]
    g, g1, g2 = d.cgf(rs)
    g_neg, g1_neg, _ = d.cgf(-rs)
    assert np.allclose(g_neg, g) and np.allclose(g1_neg, -g1)  # even g, odd g′
    for r, gi, g1i, g2i in zip(rs, g, g1, g2, strict=True):
        if name != "arcsine":  # the oracle has no arcsine density
            assert gi == pytest.approx(math.log(oracle.mgf(name, b, float(r))), rel=1e-10, abs=1e-16)
        h = 1e-4 * max(r, 1.0 / math.sqrt(b))
        gp, gm = d.cgf(np.array([r + h, r - h]))[0]
        d1p, d1m = d.cgf(np.array([r + h, r - h]))[1]
        assert g1i == pytest.approx((gp - gm) / (2 * h), rel=1e-6, abs=1e-12)
        assert g2i == pytest.approx((d1p - d1m) / (2 * h), rel=1e-5, abs=1e-10)


@pytest.mark.parametrize("name", DENSITIES)
def test_sampling_and_tilted_sampling_moments(name):
    """E x² = b and, under the tilt e^{rx}, E x = g′(r) and Var x = g″(r), within 4 standard errors."""
    b = 0.02
    d = density(name, b)
    rng = np.random.default_rng(7)
    x = d.sample(rng, 400_000)
    se = np.std(x * x) / math.sqrt(x.size)
    assert abs(np.mean(x * x) - b) <= 4 * se + 1e-12 * b  # x² is constant for the two-point density
    r = 0.5 / math.sqrt(b) if name == "laplace" else 3.0 / math.sqrt(b)
    _, g1, g2 = d.cgf(np.array([r]))
    xt = d.sample_tilted(rng, r, 400_000)
    assert abs(xt.mean() - g1[0]) < 4 * xt.std() / math.sqrt(xt.size)
    assert abs(xt.var() - g2[0]) < 4 * np.std((xt - xt.mean()) ** 2) / math.sqrt(xt.size)
    xn = d.sample_tilted(rng, -r, 400_000)  # the mirror tilt
    assert abs(xn.mean() + g1[0]) < 4 * xn.std() / math.sqrt(xn.size)


def test_density_parameterisation_and_errors():
    assert ell_of_b(b_of_ell(8.0)) == pytest.approx(8.0)
    assert Uniform(1 / 8).b == pytest.approx(
        b_of_ell(8.0)
    )  # ℓ = 1/a for the uniform density (the report's ℓ)
    assert density("C2", 0.25) == TwoPoint(0.5)
    assert density("c1", 1 / 3) == Uniform(1.0)
    with pytest.raises(ValueError, match="unknown density"):
        density("cauchy", 1.0)
    with pytest.raises(ValueError, match="finite number > 0"):
        density("uniform", -1.0)
    with pytest.raises(ValueError, match="zero mean"):
        Discrete((0.0, 1.0), (0.5, 0.5))
    with pytest.raises(ValueError, match="domain"):
        Laplace(1.0).sample_tilted(np.random.default_rng(0), 1.5, 3)


def test_model_power_and_validation():
    """T1: Mq = 3.99996; P = (N − 1)qb (3.4.13) at ℓ = 8, 4, 12."""
    m = report_model("uniform", 8.0)
    assert m.mean_active == pytest.approx(3.99996, rel=1e-12)
    assert m.power == pytest.approx(0.020833125, rel=1e-9)
    assert report_model("gaussian", 4.0).power == pytest.approx(0.0833325, rel=1e-9)
    assert report_model("two-point", 12.0).power == pytest.approx(0.0092591667, rel=1e-8)
    lam, d1, d2 = m.log_mgf(np.array([0.0]))
    assert lam[0] == 0.0 and d1[0] == 0.0 and d2[0] == pytest.approx(m.power, rel=1e-12)
    for bad, name in (((0, TA), "N"), ((10, 0.5), "tau_over_alpha"), ((10, -1.0), "tau_over_alpha")):
        with pytest.raises(ConfigError) as info:
            MANModel.common(bad[0], bad[1], Uniform(0.1))
        assert info.value.field == name
    for components, name in ((((Uniform(0.1), 8),), "components"), (((Uniform(0.1), -1),), "components")):
        with pytest.raises(ConfigError) as info:
            MANModel(10, TA, components)
        assert info.value.field == name
    with pytest.raises(ConfigError) as info:
        MANModel(10.0, TA, ((Uniform(0.1), 9),))
    assert info.value.field == "N"
    solo = MANModel.common(1, TA, Uniform(0.1))
    assert solo.trivial
    rb = roc_bounds(solo, [0.5])
    assert rb.log_pf_up[0] == -np.inf and rb.pd_lo[0] == 1.0
    assert exact_roc(solo, [0.5]).log_pf[0] == -np.inf


def test_log_mgf_derivatives_against_finite_differences_and_mixtures():
    """The w-form Λ′, Λ″ equal differences of Λ; a two-component model is the sum of its parts."""
    m = report_model("triangular", 6.0)
    r = np.array([0.5, 5.0, 40.0, 300.0])
    _, d1, d2 = m.log_mgf(r)
    h = 1e-5 * r
    lp, lm = m.log_mgf(r + h)[0], m.log_mgf(r - h)[0]
    assert np.allclose(d1, (lp - lm) / (2 * h), rtol=1e-6)
    d1p, d1m = m.log_mgf(r + h)[1], m.log_mgf(r - h)[1]
    assert np.allclose(d2, (d1p - d1m) / (2 * h), rtol=1e-5)
    a, b = Uniform(0.1), TwoPoint(0.05)
    mix = MANModel(11, 0.01, ((a, 4), (b, 6)))
    la = MANModel(5, 0.01, ((a, 4),)).log_mgf(r)[0]
    lb = MANModel(7, 0.01, ((b, 6),)).log_mgf(r)[0]
    assert np.allclose(mix.log_mgf(r)[0], la + lb, rtol=1e-13)
    assert mix.power == pytest.approx(0.02 * (4 * a.b + 6 * b.b))
    assert mix.common_density is None


# --- bounds ---------------------------------------------------------------------------------------

# T2 (ℓ = 8, θ = 0.5): ρ*, E_f, ρ₁, p_f UB, LB (report), LB (gallager), exact p_f
T2 = {
    "two-point": (18.248904, 5.124272, 25.141066, 5.950548e-3, 3.654699e-11, 1.158783e-10, 9.837969e-4),
    "uniform": (16.241929, 4.747922, 22.284389, 8.669689e-3, 1.323891e-11, 4.390116e-11, 8.236968e-4),
    "triangular": (15.168993, 4.533229, 20.770026, 1.074593e-2, 6.601871e-12, 2.253817e-11, 1.007757e-3),
    "gaussian": (14.198236, 4.337526, 19.368331, 1.306882e-2, 1.574048e-12, 5.649889e-12, 1.201290e-3),
}


@pytest.mark.parametrize("name", list(T2))
def test_spec_t2_bounds_and_exact(name):
    """T2 to the reference's 7 digits (rel. 1e-6); at θ = 0.5 the p_m side equals the p_f side."""
    m = report_model(name, 8.0)
    rho, E, rho1, up, lo_r, lo_g, ex = T2[name]
    rb = roc_bounds(m, [0.5])
    gb = roc_bounds(m, [0.5], "gallager")
    assert rb.rho_star[0] == pytest.approx(rho, rel=1e-6)
    assert rb.E_f[0] == pytest.approx(E, rel=1e-6)
    assert rb.rho1[0] == pytest.approx(rho1, rel=1e-6)
    assert math.exp(rb.log_pf_up[0]) == pytest.approx(up, rel=1e-5)
    assert math.exp(rb.log_pf_lo[0]) == pytest.approx(lo_r, rel=1e-5)
    assert math.exp(gb.log_pf_lo[0]) == pytest.approx(lo_g, rel=1e-5)
    e = exact_roc(m, [0.5])
    assert math.exp(e.log_pf[0]) == pytest.approx(ex, rel=1e-5)
    assert rb.log_pm_up[0] == pytest.approx(rb.log_pf_up[0], rel=1e-12)
    assert rb.log_pm_lo[0] == pytest.approx(rb.log_pf_lo[0], rel=1e-10)
    assert e.log_pm[0] == pytest.approx(e.log_pf[0], rel=1e-12)  # θ/A = 6.93 is off the lattice


CASES = [
    ("two-point", 4.0, 0.3),
    ("uniform", 12.0, 0.7),
    ("triangular", 6.0, 0.45),
    ("gaussian", 10.0, 0.8),
    ("laplace", 8.0, 0.25),
    ("laplace", 16.0, 0.6),
]


@pytest.mark.parametrize(("name", "ell", "theta"), CASES)
def test_bounds_against_the_oracle(name, ell, theta):
    """ρ*, E_f, γ*, E_d, ρ₁, γ₁ and both lower-bound variants against the mpmath oracle (numerical
    derivatives, bisection): agreement 1e-9 relative (measured ≤ 1e-12)."""
    b = b_of_ell(ell)
    m = MANModel.common(N, TA, density(name, b))
    rb = roc_bounds(m, [theta])
    gb = roc_bounds(m, [theta], "gallager")
    c = oracle.chernoff(name, b, N, TA, theta)
    cm = oracle.chernoff_miss(name, b, N, TA, theta)
    assert rb.rho_star[0] == pytest.approx(c["rho_star"], rel=1e-9)
    assert rb.E_f[0] == pytest.approx(c["E_f"], rel=1e-9)
    assert rb.gamma_star[0] == pytest.approx(cm["gamma_star"], rel=1e-9)
    assert rb.E_d[0] == pytest.approx(cm["E_d"], rel=1e-9)
    lo = oracle.lower_bound(name, b, N, TA, theta, "report")
    lg = oracle.lower_bound(name, b, N, TA, theta, "gallager")
    lm = oracle.lower_bound_miss(name, b, N, TA, theta, "report")
    assert rb.rho1[0] == pytest.approx(lo["rho1"], rel=1e-9)
    assert rb.log_pf_lo[0] == pytest.approx(lo["log_pf_lo"], rel=1e-9)
    assert gb.log_pf_lo[0] == pytest.approx(lg["log_pf_lo"], rel=1e-9)
    assert rb.gamma1[0] == pytest.approx(lm["gamma1"], rel=1e-9)
    assert rb.log_pm_lo[0] == pytest.approx(lm["log_pm_lo"], rel=1e-9)


@pytest.mark.parametrize(("name", "ell", "theta"), [*CASES, ("uniform", 20.0, 0.9), ("two-point", 2.0, 0.05)])
def test_exact_roc_against_the_oracle(name, ell, theta):
    """The B-spline / lattice / Gamma-series exact ROC against the oracle's multiprecision sums: 1e-9."""
    b = b_of_ell(ell)
    e = exact_roc(MANModel.common(N, TA, density(name, b)), [theta])
    o = oracle.exact(name, b, N, TA, theta)
    assert math.exp(e.log_pf[0]) == pytest.approx(o["pf"], rel=1e-9)
    assert math.exp(e.log_pm[0]) == pytest.approx(o["pm"], rel=1e-9)


def test_two_point_lattice_ties():
    """On the lattice (θ = A, one interferer reaches it exactly) p_f counts n = θ (≥) and p_m does not (>)."""
    A = 0.5
    m = MANModel.common(3, 0.1, TwoPoint(A))  # M = 2, q = 0.2
    e = exact_roc(m, [0.5])
    # n ≥ 0.5: one active at +A, or both at +A: P = 2·0.2·0.8·½ + 0.04·¼
    assert math.exp(e.log_pf[0]) == pytest.approx(2 * 0.2 * 0.8 * 0.5 + 0.04 * 0.25, rel=1e-12)
    # 1 + n < 0.5 ⇔ n < −0.5: only both at −A
    assert math.exp(e.log_pm[0]) == pytest.approx(0.04 * 0.25, rel=1e-12)
    o = oracle.exact("two-point", A**2, 3, 0.1, 0.5)
    assert math.exp(e.log_pm[0]) == pytest.approx(o["pm"], rel=1e-12)


@pytest.mark.parametrize("name", DENSITIES)
def test_exact_roc_lies_between_the_bounds_on_a_grid(name):
    """LB ≤ exact ≤ UB for both p_f and p_m, ℓ ∈ {2, 4, 8, 12, 20}, θ = 0.05 … 0.95."""
    theta = np.linspace(0.05, 0.95, 19)
    for ell in (2.0, 4.0, 8.0, 12.0, 20.0):
        m = report_model(name, ell)
        e = exact_roc(m, theta)
        for variant in ("report", "gallager"):
            rb = roc_bounds(m, theta, variant)
            slack = 1e-9
            assert np.all(e.log_pf <= rb.log_pf_up + slack)
            assert np.all(e.log_pm <= rb.log_pm_up + slack)
            assert np.all(e.log_pf >= rb.log_pf_lo - slack)
            assert np.all(e.log_pm >= rb.log_pm_lo - slack)
        if name == "two-point":  # a lattice: the ROC is a staircase in θ
            assert np.all(np.diff(e.log_pf) <= 0) and np.all(np.diff(e.log_pm) >= 0)
        else:
            assert np.all(np.diff(e.log_pf) < 0) and np.all(np.diff(e.log_pm) > 0)


def test_printed_lower_bound_sign_is_impossible():
    """With the printed φ₁ = −2ρ₁√(2Λ″) the "lower" bound exceeds 1: the corrected sign is forced."""
    for name in ("uniform", "two-point", "gaussian"):
        rb = roc_bounds(report_model(name, 8.0), np.linspace(0.2, 0.8, 7))
        printed = math.log(0.5) - rb.E_f + rb.phi1  # exp(−E_f − φ₁) with φ₁ → −φ₁
        assert np.all(printed > 0.0)
        assert np.all(rb.log_pf_lo < rb.log_pf_up)


def test_bounded_support_gives_exact_zeros():
    """θ beyond sup|n| = M·max|x|: E = ∞, p_f = 0 exactly in the bounds and the exact ROC."""
    m = MANModel.common(3, 0.1, Uniform(0.2))  # sup |n| = 0.4
    rb = roc_bounds(m, [0.3, 0.5])
    assert np.isfinite(rb.E_f[0]) and rb.E_f[1] == np.inf and rb.log_pf_lo[1] == -np.inf
    e = exact_roc(m, [0.3, 0.5])
    assert e.log_pf[1] == -np.inf and e.log_pf[0] > -np.inf


# T3: (density, ℓ, θ) → (p_f UB, p_f LB, exact p_f, p_m UB, exact p_m)
T3 = [
    ("uniform", 4.0, 0.3, 5.940872e-1, 1.404374e-5, 1.409319e-1, 7.870605e-2, 1.008608e-2),
    ("two-point", 4.0, 0.5, 2.411600e-1, 1.100145e-6, 3.899660e-2, None, None),
    ("uniform", 12.0, 0.5, 8.959011e-5, 3.557724e-16, 5.975173e-6, None, None),
    ("gaussian", 12.0, 0.7, 1.107309e-6, None, 5.453566e-8, None, None),
]


@pytest.mark.parametrize("row", T3)
def test_spec_t3(row):
    name, ell, theta, up, lo, ex, pm_up, pm_ex = row
    m = report_model(name, ell)
    rb, e = roc_bounds(m, [theta]), exact_roc(m, [theta])
    assert math.exp(rb.log_pf_up[0]) == pytest.approx(up, rel=1e-5)
    assert math.exp(e.log_pf[0]) == pytest.approx(ex, rel=1e-5)
    if lo is not None:
        assert math.exp(rb.log_pf_lo[0]) == pytest.approx(lo, rel=1e-5)
    if pm_up is not None:
        assert math.exp(rb.log_pm_up[0]) == pytest.approx(pm_up, rel=1e-5)
        assert math.exp(e.log_pm[0]) == pytest.approx(pm_ex, rel=1e-5)


# T5: upper-bound p_f at fixed p_d for C2, C1, C3, C4
T5 = {
    (8.0, 0.99): (3.4701e-3, 7.5054e-3, 1.1543e-2, 1.6997e-2),
    (10.0, 0.9): (3.9420e-7, 2.5413e-6, 6.7442e-6, 1.6260e-5),
    (6.0, 0.999): (5.5837e-1, 6.9254e-1, 7.7654e-1, 8.5532e-1),
}


@pytest.mark.parametrize(("key", "values"), list(T5.items()))
def test_spec_t5_contours_at_fixed_pd(key, values):
    ell, pd = key
    for name, want in zip(("two-point", "uniform", "triangular", "gaussian"), values, strict=True):
        m = report_model(name, ell)
        th = theta_for_pd(m, pd)
        assert math.exp(-chernoff(m, [1 - th], -1.0)[1][0]) == pytest.approx(1 - pd, rel=1e-9)
        assert math.exp(-chernoff(m, [th])[1][0]) == pytest.approx(want, rel=1e-4)


def test_spec_t6_preference_order_and_monotonicity():
    """The report's claims on the upper bound: C₂ < C₁ < C₃ < C₄ at equal ℓ and p_d; worse as ℓ falls."""
    order = ("two-point", "uniform", "triangular", "gaussian")
    for pd in (0.9, 0.99, 0.999):
        prev = None
        for ell in (12.0, 10.0, 8.0, 6.0, 4.0):
            pf = []
            for name in order:
                m = report_model(name, ell)
                th = theta_for_pd(m, pd)
                pf.append(-chernoff(m, [th])[1][0] if math.isfinite(th) else math.nan)
            pf = np.array(pf)
            ok = np.isfinite(pf)
            assert np.all(np.diff(pf[ok]) > 0), (pd, ell, pf)
            if prev is not None:
                both = ok & np.isfinite(prev)
                assert np.all(pf[both] >= prev[both] - 1e-12)
            prev = pf


def test_theorem_3_2_two_point_has_the_largest_exponent():
    """Among symmetric densities of equal b the two-point density maximises E_f (Jensen, Theorem 3.2);
    40 random symmetric discrete densities never exceed it. Exact-ROC optimality does not hold
    (uniform 8.24e-4 beats two-point 9.84e-4 at ℓ = 8, θ = 0.5)."""
    b = b_of_ell(8.0)
    theta = np.array([0.2, 0.5, 0.8])
    best = chernoff(MANModel.common(N, TA, TwoPoint(math.sqrt(b))), theta)[1]
    rng = np.random.default_rng(3)
    for _ in range(40):
        k = rng.integers(1, 6)
        x = rng.random(k) + 0.05
        w = rng.random(k)
        w = w / w.sum() / 2
        x = x * math.sqrt(b / (2 * np.dot(w, x * x)))  # second moment b
        d = Discrete(tuple(np.concatenate([x, -x])), tuple(np.concatenate([w, w])))
        assert d.b == pytest.approx(b)
        E = chernoff(MANModel.common(N, TA, d), theta)[1]
        assert np.all(E <= best * (1 + 1e-10))
    u, t = exact_roc(report_model("uniform", 8.0), [0.5]), exact_roc(report_model("two-point", 8.0), [0.5])
    assert u.log_pf[0] < t.log_pf[0]


# --- quasi-optimal density, Gaussian comparison, exponents ----------------------------------------


def test_spec_t7_closed_form_equals_numerical_sup():
    """(3.7.24) equals the numerical Chernoff sup for C* to 1e-9; the approximation (3.7.26) as in T7."""
    for Nq, ta, p, want, approx in (
        (1e5, 1e-5, 0.02, 4.851041, 4.851048),
        (50, 1e-2, 0.05, 2.020122, 2.024696),
    ):
        rho, E = quasi_optimal_exponent([0.5], p, Nq, ta)
        A = math.sqrt(p / ((Nq - 1) * 2 * ta))
        r_num, E_num = chernoff(MANModel.common(int(Nq), ta, TwoPoint(A)), [0.5])
        assert E[0] == pytest.approx(E_num[0], rel=1e-9) and rho[0] == pytest.approx(r_num[0], rel=1e-9)
        assert E[0] == pytest.approx(want, rel=1e-6)
        assert quasi_optimal_exponent_approx([0.5], p, Nq, ta)[0] == pytest.approx(approx, rel=1e-6)
    assert quasi_optimal_exponent([0.999], 1e-6, 3, 0.01)[1][0] == np.inf  # θ ≥ M·A


def test_spec_t4_gaussian_roc():
    """ROC_g (3.8.3) at the T4 points; d′ = 1/√P; Q⁻¹(p_f) + Q⁻¹(p_m) = d′; variance N vs N − 1."""
    from scipy.stats import norm

    m8 = report_model("uniform", 8.0)
    g = gaussian_roc(m8.power, [0.3, 0.5])
    assert math.exp(g.log_pf[1]) == pytest.approx(2.659856e-4, rel=1e-6)
    assert math.exp(g.log_pf[0]) == pytest.approx(1.883298e-2, rel=1e-6)
    assert math.exp(g.log_pm[0]) == pytest.approx(6.180344e-7, rel=1e-6)
    assert math.exp(gaussian_roc(report_model("uniform", 4.0).power, [0.5]).log_pf[0]) == pytest.approx(
        4.163149e-2, rel=1e-6
    )
    assert g.d_prime == pytest.approx(6.92824, rel=1e-6)
    assert norm.isf(math.exp(g.log_pf[0])) + norm.isf(math.exp(g.log_pm[0])) == pytest.approx(g.d_prime)
    assert gaussian_power(m8, "N") / gaussian_power(m8, "N-1") == pytest.approx(N / (N - 1))
    for name in DENSITIES[:4]:
        o = oracle.roc_g(b_of_ell(8.0), N, TA, 0.3)
        assert math.exp(g.log_pf[0]) == pytest.approx(o["pf"], rel=1e-12)
        assert report_model(name, 8.0).power == pytest.approx(o["P"], rel=1e-14)


def test_spec_t8_gaussian_approximation_is_optimistic_only_for_large_ell():
    """T8(a): at equal p_m the exact p_f exceeds ROC_g for ℓ ≥ 8 (all four densities, p_m = 0.1 … 0.001),
    with the reference values at ℓ = 8 (interpolated on a θ grid of step 0.005, rel. 5 %);
    it fails at ℓ = 2 (p_m = 0.1) and for C₂ at ℓ = 6, p_m = 1e-3."""
    want = {0.1: (8.2e-9, (1.6e-6, 1.4e-6, 2.6e-6, 4.6e-6)), 0.01: (2.1e-6, (4.7e-5, 4.8e-5, 7.7e-5, 1.2e-4))}
    theta = np.round(np.arange(0.005, 0.9951, 0.005), 6)

    def at_pm(m, pms):
        e, g = exact_roc(m, theta), gaussian_roc(m.power, theta)
        return [
            (pf_at_pm(theta, e.log_pf, e.log_pm, p)[1], pf_at_pm(theta, g.log_pf, g.log_pm, p)[1])
            for p in pms
        ]

    names = ("two-point", "uniform", "triangular", "gaussian")
    for i, name in enumerate(names):
        for (ex, g), (g_want, ex_want) in zip(
            at_pm(report_model(name, 8.0), list(want)), want.values(), strict=True
        ):
            assert ex == pytest.approx(ex_want[i], rel=0.05) and g == pytest.approx(g_want, rel=0.05)
    for ell in (8.0, 12.0):
        for name in names:
            for ex, g in at_pm(report_model(name, ell), (0.1, 0.01, 0.001)):
                assert ex > g
    [(ex, g)] = at_pm(report_model("uniform", 2.0), [0.1])
    assert ex < g
    [(ex, g)] = at_pm(report_model("two-point", 6.0), [0.001])
    assert ex < g


def test_spec_t9_exponent_grids():
    """(3.8.16) at the T9 values (abs 1e-4 / the rounded Fig. 3.9–3.10 grids to 1e-3); the exact form
    against the oracle's brute-force maximisation (1e-9); Exp < G, increasing in N, Exp/G falling in G."""
    assert exp_of_gaussian_exponent(4.0, 1e5, 1e-5) == pytest.approx(3.302437, abs=1e-6)
    assert exp_of_gaussian_exponent(12.5, 2e5, 1e-5) == pytest.approx(9.702096, abs=1e-6)
    assert exp_of_gaussian_exponent(12.5, 1e5, 1e-5) == pytest.approx(8.620122, abs=1e-6)
    assert exp_of_gaussian_exponent(6.25, 2e5, 1e-5) == pytest.approx(5.313610, abs=1e-6)
    fig39 = {
        1e-6: (0.200, 0.488, 1.095, 2.137, 3.302, 3.880, 3.987),
        1e-5: (0.488, 1.095, 2.137, 3.302, 3.880, 3.987, 3.999),
        1e-4: (1.096, 2.138, 3.303, 3.880, 3.987, 3.999, 4.000),
        1e-3: (2.143, 3.305, 3.881, 3.987, 3.999, 4.000, 4.000),
    }
    Ns = 10.0 ** np.arange(2, 9)
    for ta, row in fig39.items():
        got = exp_of_gaussian_exponent(4.0, Ns, ta)
        assert np.allclose(got, row, atol=1e-3)
        assert np.all(np.diff(got) > 0) and np.all(got < 4.0)
    fig310 = {
        1e4: (0.718, 1.254, 2.137, 3.565, 4.908, 5.840, 6.822),
        1e5: (0.934, 1.778, 3.302, 5.972, 8.620, 10.512, 12.542),
        2e5: (0.963, 1.869, 3.556, 6.605, 9.702, 11.943, 14.369),
        1e6: (0.992, 1.969, 3.880, 7.562, 11.520, 14.488, 17.779),
        1e7: (0.999, 1.997, 3.987, 7.948, 12.374, 15.796, 19.685),
    }
    G = np.array([1, 2, 4, 8, 12.5, 16, 20.0])
    for n, row in fig310.items():
        got = exp_of_gaussian_exponent(G, n, 1e-5)
        assert np.allclose(got, row, atol=1e-3)
        assert np.all(np.diff(got / G) < 0)
    for G1, n, ta in ((4.0, 1e5, 1e-5), (12.5, 2e5, 1e-5), (4.0, 100, 1e-3)):
        assert exp_of_gaussian_exponent_exact(G1, n, ta) == pytest.approx(
            oracle.exp_two_point_numeric(G1, n, ta), rel=1e-9
        )


# --- time–bandwidth, PSK --------------------------------------------------------------------------


def test_spec_t10_time_bandwidth():
    assert float(zakai_bandwidth_report(0.01)) == pytest.approx(0.735150, rel=1e-6)
    assert float(zakai_bandwidth_report(0.0)) == 0.75
    assert psk_power(1e5, 1.0, 0.75 / 1e-7) == pytest.approx(3.33330e-3, rel=1e-6)
    assert reference1_power(2e5, 1e7) == pytest.approx(0.0199999, rel=1e-9)
    for code in (BARKER13, MSEQ31):  # piecewise-exact ∫R² against dense numerical integration
        assert zakai_bandwidth(code) == pytest.approx(oracle.zakai_W_numeric(code), rel=1e-9)
    assert zakai_bandwidth(BARKER13) == pytest.approx(0.70028, abs=5e-6)
    assert zakai_bandwidth(MSEQ31) == pytest.approx(0.54151, abs=5e-6)


def test_psk_second_moment_is_the_quadrature_formula():
    """PSK-level b from the quadrature MGF equals (1/(6L))(1 + r₁/2) to 1e-10 and the
    oracle's exact rational enumeration; T11: b = 1/186, ℓ = √62, P = 0.02150516."""
    d = PSKAmplitude(tuple(int(v) for v in MSEQ31))
    assert d.b == pytest.approx(b_random_codes(MSEQ31), rel=1e-10)
    assert d.b == pytest.approx(float(oracle.psk_b_random(MSEQ31)), rel=1e-12)
    assert d.b == pytest.approx(1 / 186, rel=1e-12)
    assert ell_of_b(d.b) == pytest.approx(math.sqrt(62), rel=1e-12)
    assert MANModel.common(N, TA, d).power == pytest.approx(0.02150516, rel=1e-6)
    rng = np.random.default_rng(11)
    code = 1.0 - 2.0 * rng.integers(0, 2, 23)
    assert PSKAmplitude(tuple(int(v) for v in code)).b == pytest.approx(b_random_codes(code), rel=1e-10)


def _gold_family():
    from motionsig_cli.signals.gold import gold_family

    _, codes = gold_family(0o45, 0o75)
    pm = 1 - 2 * codes.astype(int)
    return pm[2], np.delete(pm, 2, axis=0)


def test_psk_family_second_moment_is_the_autocorrelation_identity():
    """(F.5): b from the cross-correlations of the Gold family (quadrature at r = 0) equals the mean of
    (1/(4τ))∫R_iiR_jj, which uses autocorrelations only, and the oracle's exact enumeration."""
    ref, fam = _gold_family()
    d = PSKAmplitude(tuple(ref), tuple(map(tuple, fam)))
    assert d.b == pytest.approx(b_from_autocorrelations(ref, fam).mean(), rel=1e-12)
    assert d.b == pytest.approx(float(oracle.psk_b_family(ref, fam)), rel=1e-12)


def test_spec_t11_psk_bounds():
    d = PSKAmplitude(tuple(int(v) for v in MSEQ31))
    rb = roc_bounds(MANModel.common(N, TA, d), [0.3, 0.5, 0.7])
    assert rb.rho_star[1] == pytest.approx(11.101933, rel=1e-6)
    assert np.exp(rb.log_pf_up) == pytest.approx([2.032591e-1, 2.705466e-2, 2.532536e-3], rel=1e-5)


@pytest.mark.parametrize("delay", [-30.3, -12.5, -0.4, 0.0, 3.75, 29.9])
def test_chip_formula_against_rf_waveform(delay):
    """Level C: an RF waveform (carrier 128 cycles/chip, FFT brick-wall low-pass at f0,
    correlation over the window) gives cos φ · X(δ) to 1e-3 (the brick-wall's ringing at chip edges);
    X also equals the oracle's direct chip-overlap sum to 1e-12."""
    rng = np.random.default_rng(5)
    intf = 1 - 2 * rng.integers(0, 2, 31)
    x = chip_correlation(MSEQ31, intf, delay)
    assert x == pytest.approx(oracle.chip_formula(MSEQ31, intf, delay), abs=1e-12)
    phase = 0.9
    assert oracle.rf_mf_output(MSEQ31, intf, delay, phase) == pytest.approx(math.cos(phase) * x, abs=1e-3)


@pytest.mark.parametrize("name", ["two-point", "uniform"])
def test_exact_roc_does_not_depend_on_the_other_thresholds(name):
    """Regression (found by the notebook's checks): the binomial sum stops per threshold, not on the
    largest value of the call; the deep tail at ℓ = 40, θ = 0.98 (p_f ~ 1e-78) was 8.7 % off beside θ = 0.02."""
    m = report_model(name, 40.0)
    both = exact_roc(m, [0.02, 0.98])
    alone = exact_roc(m, [0.98])
    assert both.log_pf[1] == pytest.approx(alone.log_pf[0], rel=1e-12)
    assert both.log_pm[0] == pytest.approx(exact_roc(m, [0.02]).log_pm[0], rel=1e-12)
    o = oracle.exact(name, b_of_ell(40.0), N, TA, 0.98)
    assert math.exp(alone.log_pf[0]) == pytest.approx(o["pf"], rel=1e-9)


@pytest.mark.parametrize("name", SCALAR)
def test_cgf_has_relative_accuracy_near_zero(name):
    """ln Φ ≈ bρ²/2 at tiny ρ to full relative precision (ln cosh and ln I₀ without cancellation): the
    exponents of huge-N models depend on it (N = 1e15 gave E_f < 0 and p_f UB > 1 before)."""
    d = density(name, 0.01)
    r = np.array([1e-12, 1e-8, 1e-5])
    g, g1, _ = d.cgf(r)
    assert np.allclose(g, 0.5 * 0.01 * r * r, rtol=1e-6)
    assert np.allclose(g1, 0.01 * r, rtol=1e-6)


@pytest.mark.parametrize("name", ["two-point", "uniform", "arcsine", "gaussian"])
def test_huge_n_exponent_tends_to_the_gaussian_one(name):
    """Theorem 3.1 in exponent form: with Mq → ∞ at fixed power, E_f(θ) → θ²/(2P) (and E ≥ 0 always)."""
    m = MANModel.common(10**15, TA, density(name, b_of_ell(8.0)))
    _, E = chernoff(m, [0.5])
    assert E[0] == pytest.approx(0.25 / (2 * m.power), rel=1e-6)


# --- the density registry: every member says what it supports ---------------------------------------

KINDS = list(REGISTRY.values())
B = 0.02


def _member(kind):
    """A density of the member: b = B, or the length-31 m-sequence for a chip-level member."""
    if kind.chip_level:
        assert kind.of_b is None and kind.from_code is not None
        return kind.from_code(tuple(int(v) for v in MSEQ31))
    assert kind.of_b is not None and kind.from_code is None
    return kind.of_b(B)


@pytest.mark.parametrize("kind", KINDS, ids=[k.name for k in KINDS])
def test_registry_member_law_is_normalised_and_gives_its_second_moment(kind):
    """Atoms sum to 1 and Σw x² = b; a pdf integrates to 1 and ∫x²C = b (adaptive quadrature over the
    support, independent of the package's own check); a mixture's draws have E x² = b within 4 SE."""
    from scipy.integrate import quad

    d = _member(kind)
    assert kind_of(d) is kind and density_kind(kind.name) is kind
    if kind.law == "atoms":
        x, w = d.atoms()
        assert w.sum() == pytest.approx(1.0, abs=1e-15) and float(np.dot(w, x * x)) == pytest.approx(
            d.b, rel=1e-14
        )
    elif kind.law == "pdf":
        edge = d.max_abs if math.isfinite(d.max_abs) else np.inf
        halves = ((-edge, 0.0), (0.0, edge))  # the pdfs have a kink or a peak at 0

        def integral(f):
            return sum(
                quad(lambda x: f(x) * float(d.pdf(np.array([x]))[0]), a, c, limit=200)[0] for a, c in halves
            )

        assert integral(lambda x: 1.0) == pytest.approx(1.0, rel=1e-6)
        assert integral(lambda x: x * x) == pytest.approx(d.b, rel=1e-6)
    else:
        assert kind.law == "mixture"
        x = d.sample(np.random.default_rng(3), 400_000)
        assert abs(np.mean(x * x) - d.b) < 4 * np.std(x * x) / math.sqrt(x.size)
    if kind.closed_form_b:
        assert d.b == pytest.approx(B, rel=1e-14)
    else:
        assert d.b == pytest.approx(b_random_codes(MSEQ31), rel=1e-10)  # the quadrature of g″(0)


@pytest.mark.parametrize("kind", KINDS, ids=[k.name for k in KINDS])
def test_exact_roc_exists_iff_the_member_says_so(kind):
    """An exact ROC is computed for a member with ``exact_roc`` (and lies between the bounds); any other
    member is refused with a ConfigError naming the density."""
    m = MANModel.common(1000, 1e-3, _member(kind))
    theta = np.array([0.3, 0.6])
    if kind.exact_roc:
        ex = exact_roc(m, theta)
        rb = roc_bounds(m, theta)
        assert np.all(ex.log_pf <= rb.log_pf_up + 1e-9) and np.all(ex.log_pm <= rb.log_pm_up + 1e-9)
        assert np.all(ex.log_pf > -np.inf)
    else:
        with pytest.raises(ConfigError) as info:
            exact_roc(m, theta)
        assert info.value.field == "density"


@pytest.mark.parametrize("kind", KINDS, ids=[k.name for k in KINDS])
def test_importance_sampling_exists_iff_the_member_says_so(kind):
    """A member with ``importance`` has a tilted sampler whose mean is g′(r); any other refuses it."""
    d = _member(kind)
    r = 0.5 / math.sqrt(d.b)
    if kind.importance:
        x = d.sample_tilted(np.random.default_rng(5), r, 200_000)
        assert abs(x.mean() - d.cgf(np.array([r]))[1][0]) < 4 * x.std() / math.sqrt(x.size)
    else:
        with pytest.raises(ConfigError) as info:
            d.sample_tilted(np.random.default_rng(5), r, 10)
        assert info.value.field == "importance"


@pytest.mark.parametrize("kind", KINDS, ids=[k.name for k in KINDS])
def test_registry_member_report_id_and_figure(kind):
    """The report's C1 … C4 name their member (in any case); a member's figure of bounds is drawn by
    ``mac-roc bounds`` for that density; the assumed shapes are exactly C1, C3, C4."""
    if kind.report_id is not None:
        assert density_kind(kind.report_id.lower()) is kind and density_kind(kind.report_id) is kind
    if kind.figure is not None:
        assert figure_command(kind.figure) == "bounds" and DENSITY_OF_FIGURE[kind.figure] == kind.name
    else:
        assert kind.name not in DENSITY_OF_FIGURE.values()
    assert kind.assumed == (kind.report_id in ("C1", "C3", "C4"))
    assert density_kind(kind.name.upper()) is kind


def test_registry_refuses_an_unknown_density_and_a_code_built_one_from_b():
    with pytest.raises(ConfigError) as info:
        density_kind("cauchy")
    assert info.value.field == "density" and "psk" in info.value.reason
    with pytest.raises(ConfigError) as info:
        density("psk", 0.1)
    assert info.value.field == "density"
    assert sorted(DENSITY_OF_FIGURE) == ["3.3", "3.4", "3.5", "3.6"]


def test_power_label_of_the_exponent_figures() -> None:
    """The legends of Figs 3.9/3.10 (`mac-roc exponent --plot`) wrote `N = 100000` next to `N = 1e+06`;
    whole multiples of a power of ten with |e| ≥ 3 are written as powers, the rest as `g` does."""
    from motionsig_cli.atc10.mac_roc import _power_label

    assert _power_label(1e5) == "$10^{5}$"
    assert _power_label(2e5) == r"$2\cdot10^{5}$"
    assert _power_label(1e-6) == "$10^{-6}$"
    assert _power_label(3e-5) == r"$3\cdot10^{-5}$"
    for v in (0.5, 100.0, 2.5e5, 0.0):
        assert _power_label(v) == f"{v:g}"
