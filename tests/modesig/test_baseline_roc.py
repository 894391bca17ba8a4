"""The LMP-against-baseline Monte Carlo: thresholds at equal P_FA, the null and signature arms' bookkeeping,
engine independence, and the measured small-signature comparison (fixed seeds)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.estimate_correlate import ECConfig
from motionsig_cli.detection.lmp import LMPConfig
from motionsig_cli.engine import Engine, run_job
from motionsig_cli.modesig.baseline_roc import DETECTORS, BaselineRocJob
from motionsig_cli.tables import format_csv


def test_no_signature_detects_at_the_false_alarm_rate() -> None:
    """With a_sig ≈ 0 the signature records are null records drawn from other streams, so each detector's
    P_D must equal its P_FA = 0.1: the in-sample rate is ≤ 0.1 by construction, the out-of-sample one has
    the binomial SE √(0.1·0.9/300) ≈ 0.017 plus the threshold's own uncertainty (≈ the same, from 300 null
    records): 4 × √2 × 0.017 ≈ 0.1 is the tolerance."""
    job = BaselineRocJob(
        a_list=(1e-9,), horizons_s=(5.0, 10.0), trials=300, null_trials=300, pfa=0.1, seed=11
    )
    res = run_job(job)
    for c in res.cells:
        assert c.false_alarms / c.null_trials <= 0.1
        assert abs(c.pd - 0.1) < 4 * math.sqrt(2) * math.sqrt(0.1 * 0.9 / 300), (
            c.detector,
            c.horizon_s,
            c.pd,
        )


def test_small_signature_detection_and_the_detrending() -> None:
    """a_sig = 0.02 at R = 1e-3 (ANR −7 dB), 10 s, P_FA = 0.05, 100 + 100 records (measured at 60 + 200: P_D 0.10
    for the LMP, 1.00 for the detrended baseline, 0.22 for the baseline without detrending). The paired
    difference must exceed 4 of its paired SEs; the detrending's gain 4 of the two binomial SEs combined
    (conservative: the two runs share their records)."""
    kw = dict(a_list=(0.02,), horizons_s=(10.0,), trials=100, null_trials=100, pfa=0.05, seed=3)
    res = run_job(BaselineRocJob(**kw))
    ec = res.cell("estimate-correlate", 0.02, 10.0)
    assert ec.diff > 4 * ec.se_diff > 0
    assert res.cell("lmp", 0.02, 10.0).diff == pytest.approx(-ec.diff)
    raw = run_job(BaselineRocJob(**kw, ec=ECConfig(detrend=0))).cell("estimate-correlate", 0.02, 10.0)
    assert ec.pd - raw.pd > 4 * math.hypot(ec.pd_se, raw.pd_se, 0.01)
    pfa, pd = res.roc("lmp", 0.02, 10.0)
    assert pfa[0] == pd[0] == 1.0 and np.all(np.diff(pfa) <= 0) and np.all(np.diff(pd) <= 0)


def test_results_do_not_depend_on_the_engine() -> None:
    job = BaselineRocJob(a_list=(0.1, 0.5), horizons_s=(2.0, 4.0), trials=6, null_trials=10, pfa=0.2, chunk=3)
    one = format_csv(run_job(job).table())
    two = format_csv(run_job(job, Engine(workers=2)).table())
    assert one == two
    assert set(run_job(job).table().column("detector")) == set(DETECTORS)


def test_bad_fields_are_refused() -> None:
    with pytest.raises(ConfigError) as err:
        BaselineRocJob(a_list=(0.0,))
    assert err.value.field == "a_list"
    with pytest.raises(ConfigError) as err:
        BaselineRocJob(example="radar", lmp=LMPConfig())
    assert err.value.field == "lmp"
    with pytest.raises(ConfigError) as err:
        BaselineRocJob(pfa=1.0)
    assert err.value.field == "pfa"
