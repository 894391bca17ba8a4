"""``motionsig simulate --f-d/--feedback``: the record carries the offset carrier and the onboard estimate,
writes both to its metadata, ``detect`` reads them back, and refusals name the option."""

import math

import numpy as np
import pytest

from motionsig_cli.modesig.record_reading import read_vehicle_record
from motionsig_cli.signals.modes import table1_codes
from tests.cli.helpers import one_line_error, run, table


def test_carrier_offset_shifts_the_signature_and_is_read_back(capsys, tmp_path):
    """--f-d 0.05: the record's z is p_k cos(2π (f_c + f_d) t + θ) (eq 3), its metadata says f_d, and the
    detector's reader puts it on the vehicle."""
    args = ("simulate", "--f-d", "0.05", "--mode", "1", "--tau", "0", "--theta", "0.3", "--duration", "3")
    rc, out, err = run(capsys, *args)
    t = table(out, tmp_path)
    assert rc == 0 and t.meta["f_d"] == 0.05 and "carrier f_c + f_d = 1.05 Hz" in err
    cols = {c: np.array([r[i] for r in t.rows], float) for i, c in enumerate(t.columns)}
    chips = 2.0 * np.asarray(table1_codes("corrected")[0], float) - 1.0  # bit 1 → +1, 0 → −1
    p = chips[(np.arange(60) // 20) % 31]
    np.testing.assert_allclose(cols["z"], p * np.cos(2 * math.pi * 1.05 * cols["t"] + 0.3), atol=1e-12)
    rec = read_vehicle_record(tmp_path / "t.csv")
    assert rec.vehicle.f_d == 0.05 and rec.vehicle.feedback == "true" and "model" not in rec.provenance


def test_estimate_feedback_record(capsys, tmp_path):
    """--feedback estimate: two more columns (the onboard estimate the controller used), the estimator in
    the metadata, read back as the vehicle's feedback; the default record has neither."""
    rc, out, _ = run(capsys, "simulate", "--feedback", "estimate", "--R", "1e-3", "--duration", "2")
    t = table(out, tmp_path)
    assert rc == 0 and t.columns[-2:] == ("xhat", "xdothat") and t.meta["feedback"] == "estimate"
    assert "own position sensor" in t.meta["onboard_estimator"]
    assert read_vehicle_record(tmp_path / "t.csv").vehicle.feedback == "estimate"
    rc, out, _ = run(capsys, "simulate", "--duration", "2")
    plain = table(out, tmp_path, "plain.csv")
    assert "xhat" not in plain.columns and plain.meta["feedback"] == "true state" and plain.meta["f_d"] == 0.0
    assert "onboard_estimator" not in plain.meta
    # the estimate loop differs from the true-state loop with the same draws
    x_est = np.array([r[t.columns.index("x")] for r in t.rows], float)
    rc, out, _ = run(capsys, "simulate", "--R", "1e-3", "--duration", "2")
    x_true = np.array([r[3] for r in table(out, tmp_path, "true.csv").rows], float)
    assert not np.allclose(x_est, x_true)


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (("--f-d", "nan"), "--f-d"),
        (("--f-d", "-2"), "--f-d"),  # f_c + f_d < 0
        (("--feedback", "observer"), "--feedback"),
        (("--example", "2d", "--feedback", "estimate"), "--feedback"),
        (("--example", "2d", "--f-d", "0.1"), "--f-d"),
    ],
)
def test_refusals_name_the_option(capsys, args, option):
    err = one_line_error(capsys, "simulate", "--duration", "1", *args)
    assert option in err
