"""detect_mode / detect_mode_radar (a record given as arrays) against the command's path on the simulated
record's own table (``motionsig simulate | motionsig detect -``: read_vehicle_record + RecordDetection)."""

from __future__ import annotations

import numpy as np
import pytest

from motionsig_cli import (
    ConfigError,
    LMPConfig,
    RadarLMPConfig,
    Vehicle1D,
    Vehicle2D,
    detect_mode,
    detect_mode_radar,
)
from motionsig_cli.modesig.lmp1d import RecordDetection
from motionsig_cli.modesig.lmp2d import RadarRecordDetection
from motionsig_cli.modesig.record_reading import read_vehicle_record
from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record


def _rows(table, name):
    return np.asarray(table.column(name))


def test_1d_equals_the_command_path_and_finds_the_truth() -> None:
    sim = simulate_record(RecordConfig(Vehicle1D(), mode=2, tau_chips=5, duration=20.0, seed=1))
    ref = RecordDetection(read_vehicle_record(sim.table), LMPConfig(), horizons=(10.0, 20.0)).detect()
    y = sim.y.copy()
    y[7] = np.nan  # a missing sample on both paths
    ref_missing = RecordDetection(
        read_vehicle_record(sim.table.__class__(sim.table.columns, [r if i != 7 else (*r[:2], "", *r[3:])
                            for i, r in enumerate(sim.table.rows)], sim.table.meta)),
        LMPConfig(), horizons=(10.0, 20.0),
    ).detect()  # fmt: skip
    for arr, want in ((sim.y, ref), (y, ref_missing)):
        det = detect_mode(sim.t, arr, horizons=[10.0, 20.0])
        assert np.array_equal(det.statistic, _rows(want.table, "statistic"))
        assert np.array_equal(det.mode, _rows(want.table, "mode_hat"))
        assert np.array_equal(det.tau, _rows(want.table, "tau_hat"))
        assert np.array_equal(det.result.Lambda, want.res.Lambda)
    assert det.mode[-1] == 2 and det.tau_chips[-1] == 5.0


def test_radar_equals_the_command_path() -> None:
    sim = simulate_record(RecordConfig(Vehicle2D(), mode=3, tau_chips=7, duration=20.0, seed=1))
    ref = RadarRecordDetection(
        read_vehicle_record(sim.table), RadarLMPConfig(), horizons=(20.0,), method="linearised"
    ).detect()
    # without a start position the model takes the first measured one (as for a user's export without
    # metadata); the simulated record's metadata holds simulate's start
    det = detect_mode_radar(
        sim.t, sim.y[:, 0], sim.y[:, 1], horizons=[20.0], method="linearised", start=Vehicle2D().start
    )
    assert np.array_equal(det.statistic, _rows(ref.table, "statistic"))
    assert (det.mode[0], det.tau_chips[0]) == (3, 7.0)


def test_bad_arguments_name_their_field() -> None:
    t = np.arange(100) * 0.05
    with pytest.raises(ConfigError) as exc:
        detect_mode(t, np.zeros(99))
    assert exc.value.field == "y"
    with pytest.raises(ConfigError) as exc:
        detect_mode(t, np.zeros(100), wobble=3)
    assert exc.value.field == "wobble"
    with pytest.raises(ConfigError) as exc:
        detect_mode(t, np.zeros(100), m_rho=0)
    assert exc.value.field == "m_rho"
