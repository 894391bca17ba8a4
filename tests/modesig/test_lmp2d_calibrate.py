"""``detect --calibrate --example 2d``: the radar threshold calibration (RadarCalibrationJob) and the CLI's
2-D --method / --calibrate / --center handling."""

import numpy as np
import pytest
from typer.testing import CliRunner

from motionsig_cli.cli.app import app
from motionsig_cli.config import ConfigError
from motionsig_cli.engine import run_job
from motionsig_cli.modesig.lmp2d import RadarCalibrationJob

SMALL = dict(anr_pairs=(2, 4), horizons_s=(4.0, 8.0), trials=4, null_trials=10, pfa=0.1, seed=3)


def test_calibration_cells_thresholds_and_false_alarms():
    """One cell per (pair, horizon); the threshold leaves at most floor(pfa * null_trials) = 1 null maximum
    above it; the ROC panels hold one curve per horizon; the null argmax statistics are in range."""
    cal = run_job(RadarCalibrationJob(**SMALL, center="standardised"))
    assert [(c.pair, c.horizon_s) for c in cal.cells] == [(1, 4.0), (1, 8.0), (2, 4.0), (2, 8.0)]
    for c in cal.cells:
        assert c.false_alarms <= 1 and 0 <= c.pd <= 1 and c.detections_correct <= c.detections
        assert 100 / 3 <= c.h0_top_mode_pct <= 100 and 0 <= c.h0_chi2_p <= 1
    panels, pfa, _ = cal.figure_data()
    assert pfa == 0.1 and len(panels) == 2 and all(len(v) == 2 for v in panels.values())
    assert cal.table().columns[-1] == "h0_argmax_chi2_p" and len(cal.table().rows) == 4


def test_calibration_is_reproducible():
    """Same seed, same cells (every trial draws from its own stream)."""
    assert run_job(RadarCalibrationJob(**SMALL)).cells == run_job(RadarCalibrationJob(**SMALL)).cells


def test_calibration_refusals():
    with pytest.raises(ConfigError, match="pfa"):
        RadarCalibrationJob(pfa=1.5)
    with pytest.raises(ConfigError, match="center"):
        RadarCalibrationJob(**{**SMALL, "method": "bank"}, center="h0-noise")
    with pytest.raises(
        ConfigError, match="trials"
    ):  # the bank's run-time estimate refuses 20/P_FA null trials
        RadarCalibrationJob(method="bank", trials=50, pfa=0.001)


def test_cli_two_d_methods_and_refusals():
    r = CliRunner()
    out = r.invoke(app, ["detect", "--calibrate", "--example", "2d", "--trials", "2", "--null-trials", "5",
                         "--pfa", "0.2", "--horizons", "3", "--anr-pairs", "4", "--quiet"])  # fmt: skip
    assert out.exit_code == 0, out.output
    assert "h0_argmax_chi2_p" in out.output and "linearised" in out.output
    bad = r.invoke(app, ["detect", "--montecarlo", "--example", "2d", "--method", "fft", "--quiet"])
    assert bad.exit_code == 2 and "--method" in bad.output
    bad = r.invoke(app, ["detect", "--montecarlo", "--method", "linearised", "--quiet"])
    assert bad.exit_code == 2 and "2d example only" in bad.output
    bad = r.invoke(app, ["detect", "--montecarlo", "--example", "2d", "--center", "h0-noise", "--quiet"])
    assert bad.exit_code == 2 and "--center" in bad.output
    mc = r.invoke(app, ["detect", "--montecarlo", "--example", "2d", "--method", "linearised", "--trials", "2",
                        "--horizons", "3", "--anr-pairs", "4", "--quiet"])  # fmt: skip
    assert mc.exit_code == 0, mc.output
    assert np.isfinite(float(mc.output.strip().splitlines()[-1].split(",")[9]))


def test_radar_record_with_a_null_threshold_on_the_linearised_path(tmp_path):
    """``detect RECORD --example 2d --method linearised --pfa P``: null records through the same path and
    centring (RecordNullJob, method linearised); at most floor(P * null trials) null maxima above each
    threshold; the calibration's identity names the centring."""
    from motionsig_cli.detection.lmp import RadarLMPConfig
    from motionsig_cli.modesig.record_calibration import RecordNullJob
    from motionsig_cli.modesig.record_reading import read_vehicle_record

    r = CliRunner()
    sim = r.invoke(app, ["simulate", "--example", "2d", "--duration", "6", "--anr-pair", "4", "--seed", "5"])
    assert sim.exit_code == 0, sim.output
    path = tmp_path / "rec.csv"
    path.write_text(sim.stdout)
    out = r.invoke(app, ["detect", str(path), "--example", "2d", "--method", "linearised", "--center",
                         "standardised", "--pfa", "0.2", "--null-trials", "10", "--horizons", "3,6", "--quiet"])  # fmt: skip
    assert out.exit_code == 0, out.output
    rows = [ln.split(",") for ln in out.stdout.strip().splitlines() if not ln.startswith("#")]
    assert rows[0][-2:] == ["threshold", "signature_present"] and len(rows) == 3
    assert all(np.isfinite(float(row[-2])) for row in rows[1:])
    rec = read_vehicle_record(path, example="2d")
    job = RecordNullJob(rec, RadarLMPConfig(fc_grid=(rec.f_c,)), "linearised", "ukf", horizons=(3.0, 6.0), pfa=0.2,
                        null_trials=10, center="standardised")  # fmt: skip
    cal = run_job(job)
    assert np.all(cal.false_alarms <= 2) and job.identity()["center"] == "standardised"
    with pytest.raises(ConfigError, match="center"):
        RecordNullJob(rec, RadarLMPConfig(), "bank", "ukf", pfa=0.2, null_trials=10, center="standardised")
