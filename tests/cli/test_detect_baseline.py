"""``detect --calibrate --detector lmp|estimate-correlate`` (modesig.baseline_calibration): the
baseline's threshold calibration on the LMP's calibration records."""

from dataclasses import replace

import numpy as np
import pytest

from motionsig_cli.engine import run_job
from motionsig_cli.modesig.baseline_calibration import BaselineCalibrationJob
from motionsig_cli.modesig.lmp1d import NULL_OFFSET, simulate_trials
from tests.cli.helpers import one_line_error, run, table

SMALL = ("detect", "--calibrate", "--trials", "4", "--null-trials", "10", "--pfa", "0.2", "--R-list", "1e-3",
         "--horizons", "5,10")  # fmt: skip


@pytest.mark.parametrize(
    ("extra", "option"),
    [((), "--detector"),  # no --calibrate: a record
     (("--montecarlo",), "--detector"), (("--calibrate", "--example", "2d"), "--detector"),
     (("--calibrate", "--Qa", "1"), "--Qa"), (("--calibrate", "--method", "fft"), "--method"),
     (("--calibrate", "--center", "h0-noise"), "--center"), (("--calibrate", "--Ar", "known"), "--Ar"),
     (("--calibrate", "--q-model", "continuous"), "--q-model"), (("--calibrate", "--filter", "ukf"), "--filter")],
)  # fmt: skip
def test_refusals_name_the_option(capsys, tmp_path, extra: tuple[str, ...], option: str) -> None:
    rec = tmp_path / "r.csv"
    rec.write_text("time,y\n0,0\n0.05,0\n")
    args = ("detect", *((str(rec),) if not extra else ()), *extra, "--detector", "estimate-correlate")
    assert option in one_line_error(capsys, *args)


def test_default_detector_is_the_lmp_byte_for_byte(capsys) -> None:
    # the option's default leaves the LMP's calibration output unchanged (same bytes as without it)
    rc0, plain, _ = run(capsys, *SMALL, "--method", "fft", "-q")
    rc1, lmp, _ = run(capsys, *SMALL, "--method", "fft", "--detector", "lmp", "-q")
    assert rc0 == rc1 == 0 and plain == lmp


def test_baseline_table_has_the_calibration_columns(capsys, tmp_path) -> None:
    rc, out, err = run(
        capsys, *SMALL, "--detector", "estimate-correlate", "-q", "--plot", str(tmp_path / "r.png")
    )
    assert rc == 0, err
    _, lmp, _ = run(capsys, *SMALL, "--method", "fft", "-q")
    t, ref = table(out, tmp_path), table(lmp, tmp_path, "l.csv")
    assert t.columns == ref.columns and len(t.rows) == len(ref.rows) == 2
    assert t.meta["detector"] == "estimate-correlate" and (tmp_path / "r.png").stat().st_size > 0
    # 10 null trials at P_FA 0.2: the threshold leaves exactly floor(0.2 * 10) = 2 null maxima above it
    assert [float(r[t.columns.index("pfa_in_sample")]) for r in t.rows] == [0.2, 0.2]


def test_records_are_those_of_the_lmp_calibration() -> None:
    # second implementation: the LMP's calibration draws its records with simulate_trials at the cell's
    # (R, f_r), signature trial t as t and null trial t as NULL_OFFSET + t
    job = BaselineCalibrationJob(R_list=(1e-2,), fr_list=(0.1,), horizons_s=(5.0,), trials=2, null_trials=2)
    cell = job.cell(0)
    veh = replace(job.vehicle, R=1e-2, f_r=0.1)
    for which, ids, sig in ((1, [0, 1], True), (0, [NULL_OFFSET, NULL_OFFSET + 1], False)):
        y, modes, _ = cell.records((which, 0, range(2)))
        y_ref, draws = simulate_trials(veh, cell.chips, 20, 1.0, 100, job.seed, ids, signature=sig)
        assert np.array_equal(y, y_ref) and list(modes) == [d.mode for d in draws]


def test_false_alarm_rate_at_the_threshold_on_fresh_null_records() -> None:
    # the threshold calibrated on n null records (seed 1), applied to n fresh null records (seed 2): their
    # false-alarm fraction is binomial about the threshold's true P_FA, itself within ~√(p(1-p)/n) of the
    # target; the SE of the difference is √(2 p(1-p)/n), and 4 SE keeps a false failure below 1e-4
    n, p, hz = 200, 0.1, (10.0,)
    cal = run_job(
        BaselineCalibrationJob(R_list=(1e-3,), horizons_s=hz, trials=1, null_trials=n, pfa=p, seed=1)
    )
    fresh = run_job(
        BaselineCalibrationJob(R_list=(1e-3,), horizons_s=hz, trials=1, null_trials=n, pfa=p, seed=2)
    )
    thr = cal.cells[0].threshold
    rate = float(np.mean(fresh.null[1e-3, 0.01][:, 0] > thr))
    assert abs(rate - p) <= 4 * np.sqrt(2 * p * (1 - p) / n), rate
    assert cal.cells[0].false_alarms == int(p * n)  # in sample: exactly floor(p n) above
