"""score_detections (SLRT on detections given as arrays): the arrays of a simulated run give the
simulation's scores bit for bit (the oracle of tests/existence/test_slrt_record.py, there through the
files); Wald's decisions are the first crossings; a bad argument is named."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from motionsig_cli import ConfigError, Sensor, SlrtRecordConfig, score_detections
from motionsig_cli.detection.sprt import first_crossing
from motionsig_cli.detection.track_existence import METHODS
from motionsig_cli.existence import slrt
from motionsig_cli.existence import slrt_record as sr


def _arrays(table, polar: bool):
    cols = table.columns
    t = np.array(table.column("time"), float)
    sensor = table.column("sensor")
    a, b = ("range [m]", "bearing [rad]") if polar else ("x [m]", "y [m]")
    z = np.array(
        [[np.nan if v is None else v for v in (r[cols.index(a)], r[cols.index(b)])] for r in table.rows]
    )
    return t, sensor, z


@pytest.mark.parametrize(
    "kw", [{}, {"clutter_rate": 0.3}, {"meas_model": "cartesian", "clutter_rate": 2.0}, {"n_sensors": 1}]
)
def test_arrays_of_a_simulated_run_give_its_scores_bit_for_bit(kw: dict) -> None:
    sc = replace(slrt.SlrtScenario(scans=15), **kw)
    study = slrt.SlrtStudy(sc, pd=(0.5,), no_target=False, runs=1, seed=11)
    sim, _ = slrt.run(study.cases[0][1], 1, 11)
    det = sr.detection_table(study)
    polar = sc.meas_model == "range_bearing"
    t, sensor, z = _arrays(det, polar)
    case = study.cases[0][1]
    sensors = [
        Sensor(sr.sensor_label(s), float(x), float(y), pd=case.pd_filter, fov=case.fov_range, clutter=case.clutter_rate,
               **({"sigma_r": case.sigma_r, "sigma_phi": math.radians(case.sigma_phi_deg)} if polar
                  else {"sigma_xy": case.sigma_r}))
        for s, (x, y) in enumerate(case.sensors)
    ]  # fmt: skip
    cfg = SlrtRecordConfig(q=sc.q, T=sc.T, init=tuple(det.meta["init"]), init_sd=tuple(det.meta["init_sd"]))
    res = score_detections(t, sensor, z, sensors, kind=sc.meas_model, config=cfg)
    assert res.methods == tuple(METHODS) and res.start.shape == (1, 4)
    for m in METHODS:
        np.testing.assert_array_equal(res.log_lr[m][0], sim[m][0])  # float-exact
        d = first_crossing(sim[m], *cfg.thresholds)
        assert res.decision[m].tolist() == d.decision.tolist()
    assert np.allclose(res.times, sc.T * np.arange(1, sc.scans + 1))


def test_bad_arguments_name_their_field() -> None:
    radar = Sensor("r1", 0.0, 0.0, pd=0.9, fov=2e4, clutter=1.0, sigma_r=10.0, sigma_phi=0.01)
    t = np.arange(1.0, 4.0)
    z = np.tile([1000.0, 0.1], (3, 1))
    cases = [
        ((t, ["r1"] * 2, z, [radar]), {}, "sensor"),
        ((t, ["r1"] * 3, z[:, :1], [radar]), {}, "measurements"),
        ((t, ["r1"] * 3, z, []), {}, "sensors"),
        ((t, ["r1"] * 3, z, [radar]), {"kind": "polar"}, "kind"),
        ((t, ["r1"] * 3, z, [radar, replace(radar, label="r2", sigma_xy=3.0)]), {}, "sigma_xy"),
    ]
    for args, kwargs, field in cases:
        with pytest.raises(ConfigError) as exc:
            score_detections(*args, **kwargs)
        assert exc.value.field == field
