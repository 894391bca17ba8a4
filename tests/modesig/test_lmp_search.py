"""The search for the mode-signature paper's regime (modesig.lmp_search): setups, scores, predictors."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import LMPConfig, RadarLMPConfig
from motionsig_cli.engine import run_job
from motionsig_cli.models.vehicle import Vehicle1D, pole_placement_gain, transition_h0
from motionsig_cli.modesig.lmp1d import LmpJob, LmpMonteCarlo
from motionsig_cli.modesig.lmp_search import (
    ANR_LABELS,
    BASELINE,
    CR_KEY_SETUPS,
    FIG3_CR,
    PAPER_READING,
    Q0_2D_FLIPPED,
    Q1_2D_FLIPPED,
    R_LN,
    RADAR_BASELINE,
    Fig3Outcomes,
    RadarSearchJob,
    RadarSetup,
    RadarSetupResult,
    SearchJob,
    Setup,
    SetupResult,
    anr_variances,
    design,
    design_radar,
    fig3_trials,
    predictors,
    reference_leak,
)
from motionsig_cli.tables import read_table

FAST = Setup("fast", Q_a=0.0, method="fft")  # the FFT path: the cheapest setup that runs every part
SHORT = replace(FAST, name="short", T=0.2, m_rho=5)  # 400 samples per 80 s record


def test_anr_units_reproduce_the_printed_labels() -> None:
    # oracle: the labels printed on Figs 3-6 (2.2, 25.3, 48.3, 94.3) and the text's "2.23"
    ln = [10 * math.log(0.125 / R) for R in anr_variances("ln")]
    assert anr_variances("ln") == R_LN
    assert np.allclose(ln, ANR_LABELS, atol=0.05) and round(ln[0], 2) == 2.23
    lg = [10 * math.log10(0.125 / R) for R in anr_variances("log10")]
    assert np.allclose(lg, ANR_LABELS, rtol=1e-12)
    with pytest.raises(ConfigError) as e:
        anr_variances("dB")
    assert e.value.field == "anr_unit"


def test_baseline_is_todays_default_and_setups_map_their_fields() -> None:
    assert BASELINE.cfg() == LMPConfig()
    assert BASELINE.vehicle(1e-3, 0.1) == Vehicle1D(R=1e-3, f_r=0.1)
    s = Setup("s", T=0.1, m_rho=10, Q_a=3.0, c_r=10.0, A_r="known", q_model="continuous", a_r=1.0,
              sigma_a=0.2, P0=5.0, wn=2 * math.pi, zeta=0.5, feedback="estimate")  # fmt: skip
    v, cfg = s.vehicle(1e-2, 0.01), s.cfg()
    assert v.K == pole_placement_gain(0.1, 2 * math.pi, 0.5)
    assert (v.T, v.a_r, v.sigma_a, v.R, v.feedback) == (0.1, 1.0, 0.2, 1e-2, "estimate")
    assert (cfg.Q_a, cfg.c_r, cfg.A_r, cfg.q_model, cfg.P0) == (3.0, 10.0, "known", "continuous", 5.0)
    assert s.cfg(c_r=1.0).c_r == 1.0
    job = s.job(2, 1)
    assert job.n_samples == 800 and job.m_rho == 10 and job.R_list == R_LN


@pytest.mark.parametrize(
    ("kw", "field"),
    [({"T": -1.0}, "T"), ({"m_rho": 0}, "m_rho"), ({"q_model": "density"}, "q_model"),
     ({"anr_unit": "x"}, "anr_unit"), ({"a_r": -1.0}, "a_r"), ({"Q_a": -1.0}, "Q_a")],
)  # fmt: skip
def test_setup_refuses_bad_fields(kw: dict, field: str) -> None:
    with pytest.raises(ConfigError) as e:
        Setup("bad", **kw)
    assert e.value.field == field


def test_fft_setup_needs_a_constant_amplitude() -> None:
    with pytest.raises(ConfigError) as e:
        SearchJob((Setup("bad", method="fft"),), trials=1)
    assert e.value.field == "method"


def test_design_is_distinct_and_labelled() -> None:
    d = design()
    assert d[0] == BASELINE
    assert len({s.name for s in d}) == len(d)
    assert len({replace(s, name="", group="") for s in d}) == len(d)  # no setup twice under two names
    assert {s.group.split(":")[0] for s in d} == {
        "baseline",
        "ofat",
        "qa100",
        "flipped",
        "grid",
        "c_r",
        "tau_grid",
    }
    # the search before c_r was free: every setup of parts 1-5 at c_r = 10^2 on the chip grid, listed first
    old = [s for s in d if s.group not in ("ofat:c_r", "c_r", "tau_grid")]
    assert d[: len(old)] == old and len(old) == 48
    assert all(s.c_r == 100.0 and s.tau_grid == "chips" for s in old)
    # c_r of Figs 4-6 takes at least 3 values around the baseline and the key setups; the sample grid is a factor
    assert {s.c_r for s in d if s.group in ("baseline", "ofat:c_r")} >= {1.0, 3.0, 100.0}
    for key in CR_KEY_SETUPS:
        assert len({s.c_r for s in d if s.name == key or s.name.startswith(f"{key} c_r=")}) >= 3
    samples = [s for s in d if s.tau_grid == "samples"]
    assert {s.c_r for s in samples if replace(s, name="", group="", c_r=100.0, tau_grid="chips") ==
            replace(BASELINE, name="", group="")} >= {1.0, 3.0, 100.0}  # fmt: skip
    with pytest.raises(ConfigError) as e:
        SearchJob((BASELINE, BASELINE), trials=1)
    assert e.value.field == "setups"


def test_search_job_equals_the_setups_own_monte_carlo() -> None:
    # second implementation: the setup's LmpJob run alone through the engine
    res = run_job(SearchJob((SHORT,), trials=3, seed=11))
    alone = run_job(SHORT.job(3, 11)).cells
    assert res.results[0].mc.cells == alone
    f3 = res.results[0].fig3
    assert set(f3) == set(FIG3_CR) and all(o.ok.shape == (3,) for o in f3.values())
    row = res.table().rows[0]
    assert row[0] == "short" and len(row) == len(res.table().columns)


def test_fig3_runs_once_for_setups_that_differ_only_in_c_r() -> None:
    # Fig 3 runs its own c_r (1, 100, 1000): a setup that differs only in the c_r of Figs 4-6 shares its runs
    other = replace(SHORT, name="c_r=3", c_r=3.0)
    job = SearchJob((SHORT, other), trials=3, seed=11)
    assert [job.fig3_source(i) for i in range(2)] == [0, 0]
    assert sum(t[0] == "fig3" for t in job.tasks()) == len(FIG3_CR)
    res = run_job(job)
    alone = run_job(SearchJob((other,), trials=3, seed=11)).results[0]
    for c in FIG3_CR:
        assert np.array_equal(res.results[1].fig3[c].ratio, alone.fig3[c].ratio)
        assert np.array_equal(res.results[1].fig3[c].ok, alone.fig3[c].ok)
    assert res.results[1].mc.cells == alone.mc.cells and res.results[1].mc.job.cfg.c_r == 3.0
    table = res.table()
    assert {"claims_held", "checks_holding", "claim1_by_ratio"} <= set(table.columns)


def test_setup_runs_the_sample_grid() -> None:
    s = replace(SHORT, name="samples", tau_grid="samples")
    assert s.cfg().tau_grid == "samples"
    job = s.job(1, 1)
    assert job.n_candidates == 3 * 31 * 5
    with pytest.raises(ConfigError) as e:
        Setup("bad", tau_grid="half-chips")  # type: ignore[arg-type]
    assert e.value.field == "tau_grid"


def test_reference_leak_is_linear_in_a_r_and_the_bank_agrees_with_the_fft_path() -> None:
    # derivation (the notebook's section 12 d): with Q_a = 0, b is linear in the data, so the ratio
    # |b_ref| / |b_sig| scales with a_r; the bank and the FFT path compute the same Λ (second implementation)
    fft = reference_leak(FAST, trials=3, seed=4)
    bank = reference_leak(replace(FAST, method="bank"), trials=3, seed=4)
    small = reference_leak(replace(FAST, a_r=1.0), trials=3, seed=4)
    assert np.allclose(fft.ratio, bank.ratio, rtol=0.02)
    assert np.allclose(small.ratio, fft.ratio / 10, rtol=1e-6)
    assert fft.ratio.min() > 3 and fft.argmax_modes == (0, 0, 3)  # mode 3, the unbalanced code
    assert reference_leak(replace(FAST, A_r="known"), trials=2, seed=4).ratio.max() < 1e-9
    assert reference_leak(FAST, f_r=0.01, trials=2, seed=4).ratio.max() < 0.01


def test_fig3_ratio_exceeds_one_exactly_when_the_truth_wins() -> None:
    out = fig3_trials(SHORT, 1.0, [0, 1, 2, 3], 5)
    assert np.array_equal(out.ok, out.ratio > 1)


def _result(ok: dict[float, np.ndarray], f3: dict[float, np.ndarray]) -> SetupResult:
    job = FAST.job(ok[R_LN[0]].shape[1], 1)
    return SetupResult(FAST, LmpMonteCarlo(job, []), ok, {c: Fig3Outcomes(v, v + 0.5) for c, v in f3.items()})


def test_scores_against_hand_computed_values() -> None:
    n, H = 10, 8  # trials, horizons 10..80 s
    ok = {R: np.ones((3, n, H), bool) for R in R_LN}
    lo = ok[R_LN[0]]
    lo[0, :2, :] = False  # Fig 4 at label 2.2: trials 0, 1 wrong at every horizon -> 80 %
    lo[1, :6, :] = False  # Fig 5 at label 2.2: 40 %
    ok[R_LN[-1]][2, :, :] = False  # Fig 6 at label 94.3: 0 %
    f3 = {1.0: np.array([True] * 2 + [False] * 8), 100.0: np.ones(n, bool), 1000.0: np.ones(n, bool)}
    sc = _result(ok, f3).scores()
    # SE = sample SD (ddof 1) / √n; for 0/1 values at p = 0.8 that is √(p(1 − p)/(n − 1))
    assert sc["claim2_pct_anr2_beyond40"].value == pytest.approx(80.0)
    assert sc["claim2_pct_anr2_beyond40"].se == pytest.approx(100 * math.sqrt(0.8 * 0.2 / (n - 1)))
    assert sc["claim2_pct_anr2_beyond40"].holds
    assert sc["claim2_anr_trend"].value == pytest.approx(20.0) and not sc["claim2_anr_trend"].holds  # 2.2 SE
    assert sc["claim3_low_anr_degradation"].value == pytest.approx(40.0)
    assert sc["claim3_fig5_minus_fig4_anr94"].value == 0.0 and sc["claim3_fig5_minus_fig4_anr94"].holds
    assert sc["claim4_pct_anr94_beyond60"].value == 0.0 and not sc["claim4"].holds
    assert sc["claim1_cr100_minus_cr1"].value == pytest.approx(80.0) and sc["claim1_cr100_minus_cr1"].holds
    assert sc["claim1_cr100_minus_cr1000"].value == 0.0 and not sc["claim1"].holds
    assert sc["fig3_ratio_cr1"].value == pytest.approx(0.7)
    # the ratio paired per trial: 100 minus 1 is 0 in trials 0-1 and 1 in trials 2-9
    assert sc["claim1_ratio_cr100_minus_cr1"].value == pytest.approx(0.8)
    assert sc["claim1_ratio_cr100_minus_cr1"].se == pytest.approx(math.sqrt(0.8 * 0.2 / (n - 1)))
    assert sc["claim1_ratio_cr100_minus_cr1"].holds and not sc["claim1_by_ratio"].holds  # 100 = 1000


def test_predictors_innovation_variance_and_the_fig6_ceiling() -> None:
    # independent derivation: the H0 filter's steady state from scipy's DARE on the printed per-step Q
    v = Vehicle1D(R=1e-5)
    P = scipy.linalg.solve_discrete_are(
        transition_h0(v).T, np.array([[1.0, 0, 0, 0]]).T, np.diag(BASELINE.Q0), np.array([[100 * 1e-5]])
    )
    p = predictors(FAST, trials=6, seed=3)
    assert p["S_bar_94.3"] == pytest.approx(P[0, 0] + 1e-3, rel=1e-9)
    assert 0.40 < p["S_bar_94.3"] < 0.42 and p["S_bar_over_cR_94.3"] > 400  # ≫ c_r R: R is inert
    # noise-free records: with no nominal reference the truth wins at f_r = f_c = 1 Hz; with a_r = 10 it
    # mostly does not (the reference leaks into the candidates); the FFT path is exact to < 1 % here
    assert predictors(replace(FAST, a_r=0.0), trials=6, seed=3)["noisefree_pct_fr1"] == 100.0
    assert p["noisefree_pct_fr1"] <= 50.0 and p["noisefree_pct_fr0.01"] == 100.0


def test_lmpjob_is_what_the_setup_runs() -> None:
    assert isinstance(FAST.job(1, 1), LmpJob)


# ------------------------------------------------------------------------------- claim 5: the radar
def test_radar_design_is_distinct_and_its_readings_are_the_printed_exponents_flipped() -> None:
    d = design_radar()
    assert d[0] == RADAR_BASELINE and d[0].cfg() == RadarLMPConfig()
    assert len({s.name for s in d}) == len(d)
    assert len({replace(s, name="", group="", trials=None) for s in d}) == len(d)
    # eq (61): 10+4 on the reference velocities read as 10-4; eq (62): every positive exponent negated
    assert Q0_2D_FLIPPED == (1e-1, 1e-3, 1e-1, 1e-3, 1e-1, 1e-4, 1e-1, 1e-4)
    assert Q1_2D_FLIPPED == (1e-1, 1e-2, 1e-1, 1e-1, 1e-2, 1e-2, 1e-2, 1e-3, 1e-1, 1e0)
    assert {s.method for s in d} == {"linearised", "bank"}
    with pytest.raises(ConfigError) as e:
        RadarSetup("bad", method="fft")  # type: ignore[arg-type]
    assert e.value.field == "method"


def test_radar_search_equals_the_setups_own_monte_carlo() -> None:
    # second implementation: the setup's RadarLmpJob run alone, its per-cell counts
    s = RadarSetup("s", c_r=1.0, T=0.1, m_rho=10)
    res = run_job(RadarSearchJob((s,), trials=2, seed=3))
    alone = run_job(s.job(2, 3)).cells
    ok = res.results[0].ok
    assert [c.correct for c in alone] == [int(ok[p, :, j].sum()) for p in range(4) for j in range(8)]
    row = res.table().rows[0]
    assert row[0] == "s" and len(row) == len(res.table().columns)


def test_claim5_scores_against_hand_computed_values() -> None:
    n = 10
    ok = np.ones((4, n, 8), bool)
    ok[2, :6, :] = False  # pair 3: 40 % at every horizon, pair 4: 100 % -> drop 60 points
    ok[3, 0, 4:] = False  # pair 4, trial 0 wrong beyond 40 s -> 90 %
    sc = RadarSetupResult(RADAR_BASELINE, ok).scores()
    assert (
        sc["claim5_pct_best_beyond40"].value == pytest.approx(90.0) and sc["claim5_pct_best_beyond40"].holds
    )
    # paired per trial, pair 4 minus pair 3: trial 0 0 - 0, trials 1-5 100 - 0, trials 6-9 100 - 100
    d = np.array([0.0] + [100.0] * 5 + [0.0] * 4)
    assert sc["claim5_drop_next"].value == pytest.approx(d.mean())
    assert sc["claim5_drop_next"].se == pytest.approx(d.std(ddof=1) / math.sqrt(n))
    assert sc["claim5"].holds
    flat = RadarSetupResult(RADAR_BASELINE, np.ones((4, n, 8), bool)).scores()  # no drop at all
    assert flat["claim5_drop_next"].value == 0.0 and not flat["claim5"].holds


def test_committed_search_varies_c_r_and_the_grid_and_the_preset_holds_the_most_checks() -> None:
    # the committed table (scripts/reproduce_lmp_search.py) against the code: its rows are design()'s,
    # c_r of Figs 4-6 takes >= 3 values, the sample grid is a factor, and --preset paper is its best row
    t = read_table(Path(__file__).resolve().parents[2] / "data" / "lmp_search.csv")
    names = t.column("name")
    assert names == [s.name for s in design()]
    assert len(set(t.numeric("c_r"))) >= 3 and set(t.column("tau_grid")) == {"chips", "samples"}
    checks = t.numeric("checks_holding", integer=True)
    i = names.index(PAPER_READING.name)
    assert checks[i] == checks.max() and design()[i] == PAPER_READING
    assert "2" in t.column("claims_held")[i]


def test_known_reference_makes_figs_4_to_6_equal_trial_by_trial() -> None:
    # derivation (notebook section 12, claim 4): the filters remove a known reference exactly from a linear
    # closed loop, so no innovation depends on f_r; with the random-walk model the 1 Hz reference leaks
    known = replace(SHORT, name="known", A_r="known")
    res = run_job(SearchJob((known, SHORT), trials=4, seed=6, fig3=False)).results
    for R in R_LN:
        ok = res[0].ok[R]
        assert np.array_equal(ok[0], ok[1]) and np.array_equal(ok[0], ok[2])
    assert res[1].scores()["claim4_fig4_minus_fig6"].value > 50
