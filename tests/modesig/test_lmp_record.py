"""The detector's result on one record: the argmax table, the candidate table and the Fig 3 grid, on a
hand-made statistic (no filters run)."""

import numpy as np
import pytest

from motionsig_cli.detection.lmp import Candidates, LMPResult
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.modesig.lmp_record import CANDIDATE_COLUMNS, record_result, sigma_meta

M_RHO, N_RHO = 2, 3  # 3 modes x 3 code phases (chips) x 1 carrier = 9 candidates, period 6 samples


def _result(best: int) -> LMPResult:
    i, t, f = np.meshgrid(np.arange(3), np.arange(0, N_RHO * M_RHO, M_RHO), [1.0], indexing="ij")
    cands = Candidates(i.ravel(), t.ravel(), f.ravel())
    lam = np.arange(9.0)[:, None, None] * np.ones((1, 1, 2))
    lam[best] = 100.0
    return LMPResult(
        cands, np.array([10, 20]), np.ones((1, 2)), np.zeros((9, 1, 2)), np.zeros((9, 1, 2)), lam
    )


@pytest.mark.parametrize(
    ("truth", "correct"), [((2, 2), True), ((2, 8), True), ((2, 4), False), ((1, 2), False)]
)
def test_argmax_table_and_correctness_modulo_the_code_period(truth, correct):
    res = _result(best=7)  # mode 3, tau 2 samples
    out = record_result(
        res, [0.5, 1.0], [10, 20], truth, {"x": 1}, (3, N_RHO), M_RHO, candidates=False, threshold=50.0
    )
    t = out.table
    assert t.columns[-4:] == ("true_mode", "true_tau", "correct", "signature_present")
    assert [row[2:4] for row in t.rows] == [(3, 2), (3, 2)]
    assert [row[-2] for row in t.rows] == [correct, correct] and [row[-1] for row in t.rows] == [True, True]
    assert t.rows[0][6] == 100.0 and t.rows[0][7] == 100.0 - 8.0  # statistic and margin to the runner-up
    assert t.meta["x"] == 1 and t.meta["n_candidates"] == 9 and t.meta["n_filters"] == 19
    assert out.summary.startswith("horizon 1 s: mode 3, tau 2 samples (1 chips)")


def test_without_truth_or_threshold():
    out = record_result(
        _result(0), [1.0, 2.0], [10, 20], None, {}, (3, N_RHO), M_RHO, candidates=False, threshold=None
    )
    assert out.table.columns[-1] == "J0" and "truth" not in out.summary


def test_candidate_table():
    out = record_result(
        _result(4), [1.0, 2.0], [10, 20], None, {}, (3, N_RHO), M_RHO, candidates=True, threshold=None
    )
    assert out.table.columns == CANDIDATE_COLUMNS and len(out.table.rows) == 18
    assert out.table.rows[4][:4] == (1.0, 2, 2, 1.0) and out.table.rows[4][-1] == 100.0


@pytest.mark.parametrize(("truth", "cell"), [((1, 4), (1, 2)), ((1, 3), None), (None, None)])
def test_statistic_grid(truth, cell):
    out = record_result(
        _result(4), [1.0, 2.0], [10, 20], truth, {}, (3, N_RHO), M_RHO, candidates=False, threshold=None
    )
    lam, got, tau_chips = out.statistic_grid()
    assert lam.shape == (3, 3) and lam[1, 1] == 100.0 and got == cell
    assert np.array_equal(tau_chips, [0.0, 1.0, 2.0])


def test_sigma_meta():
    meta = sigma_meta(SigmaPointParams(), (2, 3))
    assert meta["covariance_repairs_state"] == 2 and meta["covariance_repairs_innovation"] == 3
    assert set(meta) >= {"ut_alpha", "ut_beta", "ut_kappa"}
