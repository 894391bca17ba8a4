"""The 1-D Monte Carlo with the model options: the sample interval sets the record length, a known reference
follows each cell's f_r, the carrier offset is scored, the onboard-estimate loop draws its own stream, and
every setting reaches the table's metadata."""

from dataclasses import replace

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import LMPConfig, lmp_detect
from motionsig_cli.engine import Engine, run_job
from motionsig_cli.models.vehicle import Vehicle1D, nominal_reference, pole_placement_gain
from motionsig_cli.modesig.lmp1d import CalibrationJob, LmpJob, simulate_trials, table1_chips

CHIPS = table1_chips()
FAST = dict(cfg=LMPConfig(Q_a=0.0), method="fft", horizons_s=(10.0,), R_list=(1e-3,), trials=3)


def _run(job):
    return run_job(job, Engine(1))


def test_sample_interval_sets_the_record_length():
    """N = horizon / T: the records of T = 0.1 s are half as long as at 0.05 s for the same horizons."""
    job = LmpJob(vehicle=Vehicle1D(T=0.1, K=pole_placement_gain(0.1)), horizons_s=(10.0, 40.0))
    assert job.n_samples == 400 and job.horizon_samples == [100, 400]
    assert LmpJob(horizons_s=(10.0, 40.0)).n_samples == 800
    meta = _run(replace(job, **FAST, fr_list=(0.01,))).table().meta
    assert meta["T"] == 0.1 and meta["K"] == list(pole_placement_gain(0.1))


def test_known_reference_uses_each_cells_f_r():
    """A_r known: the task's records of every f_r are detected with their own reference (a direct call per
    f_r with that reference gives the same argmax and λ*)."""
    cfg = LMPConfig(A_r="known", Q_a=0.0)
    job = LmpJob(cfg, fr_list=(0.01, 1.0), R_list=(1e-3,), horizons_s=(20.0,), trials=2, method="bank")
    out = job.run_task((1e-3, range(2)))
    for f, fr in enumerate((0.01, 1.0)):
        veh = replace(job.vehicle, R=1e-3, f_r=fr)
        y, _ = simulate_trials(veh, job.chips, 20, 1.0, job.n_samples, job.seed, [0, 1])
        res = lmp_detect(y, job.chips, veh, 20, cfg, job.horizon_samples)
        np.testing.assert_allclose(out.lam_max[f], res.best()[1], rtol=1e-10)
    with_ref = job.references(2)
    assert with_ref.shape == (4, job.n_samples, 2)
    np.testing.assert_array_equal(
        with_ref[3], nominal_reference(replace(job.vehicle, f_r=1.0), np.arange(400) * 0.05)
    )
    assert LmpJob().references(2) is None


def test_carrier_offset_is_scored_and_recorded():
    """f_d ≠ 0 with a carrier grid: the table adds pct_fc_correct and fc_rmse, the metadata f_d and the true
    carrier; the default table has neither (its columns are unchanged)."""
    grid = (0.98, 1.0, 1.02)
    cfg = LMPConfig(Q_a=0.0, fc_grid=grid, A_r="known", Q0=(1e-6, 1e-4, 0.0, 0.0), c_r=1.0)
    job = LmpJob(**{**FAST, "cfg": cfg, "horizons_s": (40.0,)}, fr_list=(0.01,), vehicle=Vehicle1D(f_d=0.02))
    t = _run(job).table()
    assert t.columns[-2:] == ("pct_fc_correct", "fc_rmse")
    row = dict(zip(t.columns, t.rows[0], strict=True))
    assert row["pct_fc_correct"] == 100.0 and row["fc_rmse"] == pytest.approx(0.0, abs=1e-12)
    assert t.meta["f_d"] == 0.02 and t.meta["f_true"] == pytest.approx(1.02)
    plain = _run(LmpJob(**FAST, fr_list=(0.01,))).table()
    assert "pct_fc_correct" not in plain.columns and "f_d" not in plain.meta and "q_model" not in plain.meta


def test_estimate_feedback_draws_its_own_stream_per_trial():
    """feedback=estimate: a trial's record does not depend on the batch it is simulated in (stream
    (seed, t, 3)), and differs from the true-state loop's."""
    veh = Vehicle1D(R=1e-3, feedback="estimate")
    both, _ = simulate_trials(veh, CHIPS, 20, 1.0, 200, 9, [4, 5])
    alone, _ = simulate_trials(veh, CHIPS, 20, 1.0, 200, 9, [5])
    np.testing.assert_array_equal(both[1], alone[0])
    true, _ = simulate_trials(Vehicle1D(R=1e-3), CHIPS, 20, 1.0, 200, 9, [5])
    assert not np.allclose(true, alone)
    meta = _run(LmpJob(**FAST, fr_list=(0.01,), vehicle=Vehicle1D(feedback="estimate"))).table().meta
    assert meta["feedback"] == "estimate" and "own position sensor" in meta["onboard_estimator"]


def test_model_checks_name_the_field():
    with pytest.raises(ConfigError) as exc:
        LmpJob(vehicle=Vehicle1D(f_d=-1.5))
    assert exc.value.field == "f_d"
    with pytest.raises(ConfigError) as exc:
        LmpJob(cfg=LMPConfig(q_model="continuous"), vehicle=Vehicle1D(K=(0.0, 50.0)))
    assert exc.value.field == "q_model"


def test_calibration_records_a_non_default_vehicle_and_identity_changes():
    veh = Vehicle1D(a_r=1.0, sigma_a=0.02)
    job = CalibrationJob(LMPConfig(Q_a=0.0), (0.01,), (1e-3,), (10.0,), 2, 10, 0.1, method="fft", vehicle=veh)
    meta = _run(job).table().meta
    assert meta["a_r"] == 1.0 and meta["sigma_a"] == 0.02 and meta["feedback"] == "true"
    plain = replace(job, vehicle=Vehicle1D())
    assert "a_r" not in _run(plain).table().meta
    assert (
        job.identity() != plain.identity() and LmpJob().identity() == LmpJob(vehicle=Vehicle1D()).identity()
    )
