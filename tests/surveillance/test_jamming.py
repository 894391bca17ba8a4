"""ATC-10 §2 jamming bounds (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972): the formulas
against an independent mpmath implementation (``jam_oracle``, direct non-log form, numeric ν
maximisation, bisection), reference values of a second independent implementation written from the
report's equations, and the printed tables.

Tolerances: float log-domain vs 50-digit direct evaluation — 1e-9 relative on ln N̄ (both are
exact to double precision apart from ndtri/log_ndtr rounding, ~1e-14), 1e-6 dB on thresholds
(the oracle bisects to 1e-9 dB). The reference values are printed to 7–10 digits: 1e-6 relative.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance import jamming as jam
from motionsig_cli.surveillance.jamming import (
    JammingSystem,
    detection_exponent,
    log_bound,
    log_supremum,
    p_d_for,
    p_dl,
    required_jamming,
    t_for,
)
from tests.surveillance import jam_oracle as oracle

S = JammingSystem()
LN10 = math.log(10.0)


def design(K, pdl, t=0.0):
    return jam.JammingDesign.from_pdl(K, pdl, t)


# --- reference values: system constants, P_DL, ν*, E ----------------------------------------------------


def test_sample_counts_and_eb():
    assert S.n_alpha == 2.0e7 and S.n_beta == pytest.approx(9.6e5, rel=1e-15)
    assert S.n_v == pytest.approx(23.858639, rel=1e-7)
    assert S.eb_dbw == pytest.approx(50.0, abs=1e-12)  # E·B = 0.01 J × 1e7 Hz = 1e5 W


@pytest.mark.parametrize(
    ("p_d", "K", "t", "expected", "nu", "E"),
    [
        (0.9, 10, 0.1, 0.9988605978, 2.84318688, 0.6777251583),
        (0.8, 100, 0.2, 0.9999531070, 1.02067516, 0.0996764221),
        (0.95, 10, 0.5, 0.9193845156, 1.47956091, 0.2518064533),
        (0.5, 1000, 0.05, 0.7596809460, None, 0.0014257878),
        (0.7, 10, 0.3, 0.0, 0.0, 0.0),  # t ≥ q = 0.2401: the bound is useless
        (0.9, 1, 0.0, 0.6561, None, None),  # eq 2.4.1
    ],
)
def test_pdl_reference_values(p_d, K, t, expected, nu, E):
    assert float(p_dl(p_d, K, t)) == pytest.approx(expected, rel=1e-9, abs=1e-12)
    if nu is not None:
        assert float(jam.chernoff_nu(p_d**4, t)) == pytest.approx(nu, abs=6e-9)  # printed to 8 decimals
    if E is not None:
        assert float(detection_exponent(p_d**4, t)) == pytest.approx(E, abs=6e-11)  # printed to 10 decimals


@pytest.mark.parametrize("q", [0.05, 0.3, 0.6561, 0.9, 0.999])
@pytest.mark.parametrize("t", [0.01, 0.1, 0.3, 0.5, 0.8])
def test_closed_form_exponent_is_the_numeric_maximum(q, t):
    """A.18: E(t, q) = max_ν f(ν); the maximiser is ν* (bounded Brent on f, an independent route)."""
    f = lambda nu: nu * (1 - t) - math.log((1 - q) * math.exp(nu) + q)  # noqa: E731
    res = minimize_scalar(lambda nu: -f(nu), bounds=(0.0, 60.0), method="bounded", options={"xatol": 1e-12})
    assert float(detection_exponent(q, t)) == pytest.approx(max(-res.fun, f(0.0)), abs=1e-11)
    if t < q:
        assert float(jam.chernoff_nu(q, t)) == pytest.approx(res.x, abs=1e-5)


@pytest.mark.parametrize(
    ("p_d", "K", "t"), [(0.9, 10, 0.1), (0.6, 100, 0.05), (0.3, 1000, 0.0), (0.99, 10, 0.8)]
)
def test_pdl_against_mpmath_numeric_maximisation(p_d, K, t):
    assert float(p_dl(p_d, K, t)) == pytest.approx(float(oracle.p_dl(p_d, K, t)), rel=1e-12)


P_D_TABLE = {  # reference values: p_d solving K·D(t‖p_d⁴) = −ln(1 − P_DL), t = 0, 0.1, 0.2, 0.3, 0.5
    (10, 0.88): (0.661136, 0.789453, 0.847402, 0.887926, 0.943946),
    (10, 0.999): (0.840397, 0.901795, 0.933148, 0.954895, 0.982725),
    (100, 0.88): (0.380582, 0.644716, 0.733892, 0.794793, 0.880801),
    (100, 0.999): (0.508283, 0.704071, 0.780641, 0.833551, 0.907956),
    (1000, 0.88): (0.214527, 0.589374, 0.690154, 0.758145, 0.854250),
    (1000, 0.98): (0.249970, 0.598846, 0.697649, 0.764449, 0.858871),
    (1000, 0.999): (0.288044, 0.610487, 0.706856, 0.772180, 0.864508),
}


@pytest.mark.parametrize(("K", "pdl"), list(P_D_TABLE))
def test_design_inversion_table_and_roundtrip(K, pdl):
    for t, expected in zip((0.0, 0.1, 0.2, 0.3, 0.5), P_D_TABLE[(K, pdl)], strict=True):
        p_d = p_d_for(K, pdl, t)
        assert p_d == pytest.approx(expected, abs=6e-7)  # printed to 6 decimals
        assert float(p_dl(p_d, K, t)) == pytest.approx(pdl, rel=1e-12)  # the round trip
        if t > 0:
            assert t_for(K, p_d, pdl) == pytest.approx(t, abs=1e-9)


def test_design_inversion_against_mpmath_bisection():
    for K, pdl, t in [(10, 0.999, 0.9), (100, 0.88, 0.3), (1000, 0.999, 0.0), (1, 0.9, 0.0)]:
        assert p_d_for(K, pdl, t) == pytest.approx(float(oracle.pd_for(K, pdl, t)), rel=1e-11)


def test_design_edges():
    with pytest.raises(ValueError, match="K = 1"):
        p_d_for(1, 0.9, 0.1)
    with pytest.raises(ConfigError, match=r"pdl = 1 is not in \(0, 1\)"):
        p_d_for(10, 1.0)
    with pytest.raises(ValueError, match="infeasible"):
        t_for(10, 0.3, 0.999)  # even t = 0 gives 1 − (1 − 0.0081)^10 ≈ 0.078
    assert float(detection_exponent(1.0, 0.5)) == math.inf  # q = 1: P_DL = 1
    # K = 10, P_DL = 0.999, t = 0.9 needs q = 0.99996: resolved through w = ln(1 − q)
    assert p_d_for(10, 0.999, 0.9) ** 4 == pytest.approx(float(oracle.pd_for(10, 0.999, 0.9)) ** 4, rel=1e-13)


# --- p_f (App. D) -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("x", "p_d", "expected"),
    [
        (-16, 0.974004, 6.3163208e-6),
        (0, 0.5, 0.15865525),
        (10, 0.288044, 0.19069561),
        (-20, 0.99, 8.3583531e-15),
    ],
)
def test_pf_reference_values_and_erf_form(x, p_d, expected):
    got = math.exp(float(jam.log_pf(x, p_d)))
    assert got == pytest.approx(expected, rel=1e-7)
    assert got == pytest.approx(float(oracle.pf(x, p_d)), rel=1e-12)  # ½ − ½ erf(√(P₀Bτ/2J) − φ)


def test_pf_far_tail_is_not_zero():
    """x = −40 dB: p_f ≈ 1e−2173, far below the smallest double; ln p_f stays exact."""
    lp = float(jam.log_pf(-40.0, 0.9))
    assert lp / LN10 == pytest.approx(float(oracle.mp.log10(oracle.pf(-40.0, 0.9))), rel=1e-12)


def test_misprinted_form_is_the_correct_one_at_twice_the_power():
    """2.8.1's ½√(P₀Bτ/J) equals √(P₀Bτ/2J) at J doubled: a shift of 10·log10 2 dB, exactly."""
    rep = JammingSystem(pf_form="report")
    d = design(100, 0.88)
    x = np.linspace(-20, 0, 41)
    assert np.allclose(
        log_bound("nfl", x - 10 * math.log10(2), d, rep), log_bound("nfl", x, d, S), rtol=1e-12
    )
    assert np.array_equal(log_bound("nadl", x, d, rep), log_bound("nadl", x, d, S))  # 2.8.4 is printed right
    d1 = design(1, 0.9)  # K = 1 uses 2.7.1, printed right
    assert np.array_equal(log_bound("nfl", x, d1, rep), log_bound("nfl", x, d1, S))


# --- the bounds ---------------------------------------------------------------------------------


def test_log_window_matches_direct_formula_and_series():
    for p in (1e-3, 1e-7, 1e-12, 3e-20):
        for n in (23.858639, 9.6e5, 2e7):
            direct = math.log(-math.expm1(n * math.log1p(-p)))
            assert float(jam.log_window(math.log(p), n)) == pytest.approx(direct, rel=1e-9)
    # p below the smallest double: ln(1 − (1−p)^n) = ln n + ln p to O(np)
    assert float(jam.log_window(-2000.0, 2e7)) == pytest.approx(math.log(2e7) - 2000.0, rel=1e-15)


BOUND_VALUES = [  # reference values (fractions of N_T, t = 0 unless given): (K, P_DL, t, x, quantity, value or log10)
    (1, 0.9, 0.0, -18, "nfl", 1.488712e-11, False),
    (1, 0.9, 0.0, -18, "nadl", 7.443562e-13, False),
    (1, 0.9, 0.0, -16, "nfl", 0.8937342, False),
    (1, 0.9, 0.0, -16, "nadl", 0.04468671, False),
    (1, 0.9, 0.0, -14, "nfl", 0.9, False),
    (1, 0.9, 0.0, -14, "nadl", 0.045, False),
    (10, 0.88, 0.0, -14, "nfl", 0.5989718, False),
    (10, 0.88, 0.0, 0, "nadl", 0.04352531, False),
    (10, 0.88, 0.0, -16, "nfl", -9.706300, True),
    (10, 0.88, 0.0, -16, "nadl", -222.276255, True),
    (100, 0.999, 0.0, 0, "nadl", 7.501595e-4, False),
    (100, 0.999, 0.0, 10, "nadl", 4.980764e-2, False),
    (100, 0.999, 0.0, -14, "nfl", 1.408858e-2, False),
    (1000, 0.999, 0.0, 30, "nadl", 1.373372e-2, False),
    (1000, 0.999, 0.0, 10, "nadl", 2.055050e-10, False),
    (1000, 0.999, 0.0, -14, "nfl", 3.554910e-7, False),
    (10, 0.88, 0.2, -8, "nadl", -3.735775, True),
    (100, 0.999, 0.1, -3, "nadl", -2.139566, True),
    (1000, 0.98, 0.0, 40, "nadl", -2.816150, True),
    (10, 0.999, 0.5, -16, "nfl", -0.045774, True),
    (10, 0.999, 0.5, -16, "nadl", -95.514678, True),
]


@pytest.mark.parametrize(("K", "pdl", "t", "x", "q", "value", "is_log10"), BOUND_VALUES)
def test_bounds_reference_values(K, pdl, t, x, q, value, is_log10):
    got = float(log_bound(q, x, design(K, pdl, t), S))
    if is_log10:
        assert got / LN10 == pytest.approx(value, abs=1.5e-6 * max(1.0, abs(value)))
    else:
        assert math.exp(got) == pytest.approx(value, rel=1e-6)


@pytest.mark.parametrize(
    ("K", "t"), [(1, 0.0), (10, 0.0), (10, 0.3), (100, 0.0), (100, 0.3), (1000, 0.0), (1000, 0.3)]
)
def test_bounds_against_mpmath_over_the_whole_range(K, t):
    """From 1e−2000 to the plateau, both bounds, both p_f forms (N̄_FL)."""
    d = design(K, 0.999 if K > 1 else 0.9, t)
    rep = JammingSystem(pf_form="report")
    for x in (-30.0, -17.0, -12.0, -5.0, 3.0, 25.0, 60.0):
        for q in ("nfl", "nadl"):
            ours = float(log_bound(q, x, d, S)) / LN10
            ref = oracle.log10_nfl(x, d.p_d, K, t) if q == "nfl" else oracle.log10_nadl(x, d.p_d, K, t)
            assert ours == pytest.approx(float(ref), rel=1e-9, abs=1e-12), (q, x)
        ours = float(log_bound("nfl", x, d, rep)) / LN10
        assert ours == pytest.approx(
            float(oracle.log10_nfl(x, d.p_d, K, t, form="report")), rel=1e-9, abs=1e-12
        )


@pytest.mark.parametrize(
    ("K", "pdl", "sup"),
    [(1000, 0.88, 3.469e-6), (1000, 0.98, 2.128e-3), (1000, 0.999, 2.021e-2), (100, 0.88, 0.04386)],
)
def test_suprema(K, pdl, sup):
    assert math.exp(log_supremum("nadl", design(K, pdl), S)) == pytest.approx(
        sup, rel=5e-4
    )  # printed to 4 digits
    assert math.exp(log_supremum("nfl", design(K, pdl), S)) == pytest.approx(0.9, rel=1e-12)  # N_T − N


# --- thresholds (§7.3) ----------------------------------------------------------------------------

X_STAR = {  # reference values: x* (dB) of N̄_ADL = 0.01 N_T
    (1, 0.88, 0.0): -16.413,
    (1, 0.9, 0.0): -16.525,
    (1, 0.999, 0.0): -18.331,
    (10, 0.88, 0.0): -4.1527,
    (10, 0.999, 0.0): -6.8835,  # the reference prints −6.884; both implementations give −6.88349
    (100, 0.88, 0.0): 5.349,
    (100, 0.98, 0.0): 2.998,
    (100, 0.999, 0.0): 1.162,
    (1000, 0.999, 0.0): 25.732,
    (10, 0.88, 0.1): -6.029,
    (10, 0.88, 0.5): -8.900,
    (100, 0.999, 0.1): -2.861,
    (1000, 0.999, 0.1): 0.999,
    (1000, 0.999, 0.3): -2.651,
}


@pytest.mark.parametrize(("K", "pdl", "t"), list(X_STAR))
def test_threshold_reference_values_and_oracle(K, pdl, t):
    d = design(K, pdl, t)
    th = required_jamming("nadl", 0.01, d, S)
    assert th.attainable
    assert th.x_db == pytest.approx(X_STAR[(K, pdl, t)], abs=1e-3)
    assert th.x_db == pytest.approx(float(oracle.threshold_x("nadl", 0.01, d.p_d, K, t)), abs=1e-6)
    assert th.erp_dbw == pytest.approx(th.x_db + 50.0, abs=1e-9)


@pytest.mark.parametrize(
    ("K", "pdl", "t", "q", "level"),
    [
        (10, 0.88, 0.0, "nfl", 0.45),
        (1000, 0.999, 0.2, "nfl", 0.45),
        (100, 0.999, 0.3, "nadl", 1e-5),
        (1000, 0.999, 0.0, "nadl", 1e-200),
    ],
)
def test_two_stage_solve_matches_direct_brent_in_x(K, pdl, t, q, level):
    """The two-stage solve in u = ln p_f against a direct Brent solve in x on the log bound must agree to 1e−6 dB."""
    d = design(K, pdl, t)
    th = required_jamming(q, level, d, S)
    x = brentq(lambda x: float(log_bound(q, x, d, S)) - math.log(level), -100.0, 200.0, xtol=1e-12)
    assert th.x_db == pytest.approx(x, abs=1e-6)


@pytest.mark.parametrize(("K", "pdl"), [(1000, 0.88), (1000, 0.98)])
def test_unattainable_targets(K, pdl):
    th = required_jamming("nadl", 0.01, design(K, pdl), S)
    assert not th.attainable and th.x_db == math.inf
    assert oracle.threshold_x("nadl", 0.01, p_d_for(K, pdl), K, 0.0) is None
    with pytest.raises(ValueError, match="supremum"):  # 0.9 N_T = N_T − N is the supremum itself: invalid
        required_jamming("nfl", 0.9, design(10, 0.88), S)
    # a level within rounding of the supremum is unattainable, not a crash (d* would be 0)
    d = design(1000, 0.999)
    assert not required_jamming("nadl", math.exp(log_supremum("nadl", d, S)) * (1 - 1e-15), d, S).attainable


def test_k1000_is_flagged_ill_conditioned():
    th = required_jamming("nadl", 0.01, design(1000, 0.999), S)
    assert th.ill_conditioned and 0.9 < th.pf_over_pd < 1
    assert not required_jamming("nadl", 0.01, design(10, 0.88), S).ill_conditioned


# --- the report's qualitative claims (§2.8 text) -----------------------------------------------------

FIG_SETS = [(10, 0.88), (10, 0.999), (100, 0.88), (100, 0.999), (1000, 0.999)]


@pytest.mark.parametrize(("K", "pdl"), FIG_SETS)
def test_lower_t_makes_jamming_harder_and_nfl_degrades_first(K, pdl):
    xs_adl, xs_fl = [], []
    for t in (0.5, 0.3, 0.2, 0.1, 0.0):
        d = design(K, pdl, t)
        xs_adl.append(required_jamming("nadl", 0.01, d, S).x_db)
        xs_fl.append(required_jamming("nfl", 0.45, d, S).x_db)
    assert all(np.diff(xs_adl) > 0), xs_adl  # N̄_ADL crossing moves right as t decreases
    assert all(f < a for f, a in zip(xs_fl, xs_adl, strict=True))  # N̄_FL degrades at lower power
    assert np.ptp(xs_fl) < np.ptp(xs_adl)  # N̄_FL less sensitive to t


def test_bounds_increase_with_jammer_power_and_p_d_and_decrease_with_K():
    x = np.linspace(-30, 80, 2201)
    for K, pdl, t in [(1, 0.9, 0.0), (10, 0.88, 0.2), (1000, 0.999, 0.0)]:
        for q in ("nfl", "nadl"):
            assert np.all(np.diff(log_bound(q, x, design(K, pdl, t), S)) >= 0)
    # p_f rises with p_d at fixed x, hence both bounds (fixed K, t)
    lo, hi = jam.JammingDesign(10, 0.7, 0.1), jam.JammingDesign(10, 0.8, 0.1)
    assert np.all(log_bound("nfl", x, hi, S) >= log_bound("nfl", x, lo, S))
    # larger K at the same P_DL needs smaller p_d: the jammer needs more power
    xs = [required_jamming("nadl", 0.01, design(K, 0.999), S).x_db for K in (1, 10, 100, 1000)]
    assert all(np.diff(xs) > 0)


@pytest.mark.parametrize("pdl", [0.88, 0.999])
def test_about_ten_db_per_decade_of_K(pdl):
    """§2.8: "about 10 db more power to disable a K = 10 system than K = 1, and about 10 db more for K = 100"."""
    e = [required_jamming("nadl", 0.01, design(K, pdl), S).erp_dbw for K in (1, 10, 100)]
    assert 7 < e[1] - e[0] < 13 and 7 < e[2] - e[1] < 13


def test_k1_pdl_spread_below_two_db():
    """§2.7: "the difference between required jamming power for a P_DL of 0.9 and 0.999 is less than 2 db"."""
    for q, level in (("nadl", 0.01), ("nfl", 0.45)):
        a = required_jamming(q, level, design(1, 0.9), S).x_db
        b = required_jamming(q, level, design(1, 0.999), S).x_db
        assert 0 < a - b < 2


def test_system_validation():
    for bad in (
        {"bandwidth_hz": 0.0},
        {"airborne_frac": 1.0},
        {"vmax_mph": 1e12},
        {"pf_form": "x"},
        {"energy_j": math.nan},
    ):
        with pytest.raises(ValueError):
            JammingSystem(**bad)
    with pytest.raises(ConfigError, match=r"level = 1.5 is not in \(0, 1\]"):
        required_jamming("nadl", 1.5, design(10, 0.88), S)
    with pytest.raises(ValueError, match="double precision"):
        p_d_for(10**29, 0.9, 0.3)  # q would need to be t + 1e-15: refused, not silently wrong
    with pytest.raises(ValueError, match="K = 1"):
        t_for(1, 0.99, 0.5)


def test_exponent_stable_when_q_is_close_to_t():
    """Large K needs q − t ~ 1e−5: D(t‖q) ≈ (q−t)²/(2t(1−t)); the cancelling direct form loses ~6 digits."""
    for K in (10**6, 10**9):
        p = p_d_for(K, 0.9, 0.1)
        assert float(p_dl(p, K, 0.1)) == pytest.approx(0.9, rel=1e-12)
        assert float(p_dl(p, K, 0.1)) == pytest.approx(float(oracle.p_dl(p, K, 0.1)), rel=1e-12)
