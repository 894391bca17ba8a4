"""One simulated record (``simulate``): the checks of its configuration, the record against the closed-loop
models it runs, and the refusals of a record that cannot be simulated."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.models.vehicle import Vehicle1D, simulate_1d
from motionsig_cli.models.vehicle2d import Vehicle2D, anr_pair_variances
from motionsig_cli.modesig.lmp1d import draw_trial, signature_batch
from motionsig_cli.modesig.vehicle_record import (
    COLUMNS_1D,
    COLUMNS_2D,
    MAX_RECORD,
    RecordConfig,
    simulate_record,
)
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import table1_codes

V1, V2 = Vehicle1D(R=1e-3), Vehicle2D()
CHIPS = to_bipolar(table1_codes("corrected")).astype(float)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"vehicle": "car"}, "vehicle"),
        ({"mode": 0}, "mode"),
        ({"mode": 4}, "mode"),
        ({"mode": 1.5}, "mode"),
        ({"tau": 1.5}, "tau"),
        ({"tau": 2**53 + 1}, "tau"),
        ({"tau": 3, "tau_chips": 1}, "tau_chips"),
        ({"tau_chips": 2**50}, "tau_chips"),  # 2^50 chips x 20 samples > 2^53
        ({"tau_chips": 0.5}, "tau_chips"),
        ({"theta": math.inf}, "theta"),
        ({"theta": math.nan}, "theta"),
        ({"f_c": -1.0}, "f_c"),
        ({"m_rho": 0}, "m_rho"),
        ({"duration": 0.0}, "duration"),
        ({"duration": -5.0}, "duration"),
        ({"duration": math.nan}, "duration"),
        ({"duration": 0.02}, "duration"),  # shorter than one sample
        ({"duration": (MAX_RECORD + 1) * 0.05}, "duration"),
        ({"codes": "gold"}, "codes"),
        ({"zdot": "numeric"}, "zdot"),
        ({"signature": "yes"}, "signature"),
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"anr_pair": 2}, "anr_pair"),  # a 1-D vehicle
        ({"vehicle": V2, "anr_pair": 5}, "anr_pair"),
        ({"vehicle": V2, "anr_pair": 2}, "anr_pair"),  # not the pair of the vehicle's variances
    ],
)
def test_every_field_is_checked(kwargs, field):
    with pytest.raises(ConfigError) as exc:
        RecordConfig(**{"vehicle": V1, **kwargs})
    assert exc.value.field == field


def test_samples_and_example():
    assert RecordConfig(V1, duration=20.0).n_samples == 400 and not RecordConfig(V1).two_d
    assert RecordConfig(V1, duration=MAX_RECORD * 0.05).n_samples == MAX_RECORD
    pair2 = Vehicle2D(R_range=anr_pair_variances(2)[0], R_bearing=anr_pair_variances(2)[1])
    assert RecordConfig(pair2, anr_pair=2).two_d


def test_1d_record_is_trial_0_of_the_closed_loop():
    """Rows: the closed loop (eqs 53–55) on trial 0's draws, with the given mode and code phase."""
    rec = simulate_record(RecordConfig(V1, mode=3, tau_chips=7, duration=10.0, seed=11))
    n = 200
    draw = draw_trial(11, 0, n, 3, 31, 20)
    z, zd = signature_batch(CHIPS, np.array([2]), np.array([140]), np.array([draw.theta]), 1.0, 0.05, 20, n)
    sim = simulate_1d(V1, z, zd, draw.w[None], draw.v[None])
    t = rec.table
    assert t.columns == COLUMNS_1D and len(t.rows) == n
    cols = {c: np.array([row[j] for row in t.rows]) for j, c in enumerate(t.columns)}
    assert np.array_equal(cols["y"], sim["y"][0]) and np.array_equal(cols["x"], sim["x"][0, :, 0])
    assert np.array_equal(cols["z"], z[0]) and np.array_equal(cols["u"], sim["u"][0])
    assert t.meta["mode"] == 3 and t.meta["tau"] == 140 and t.meta["tau_chips"] == 7.0
    assert t.meta["theta"] == draw.theta and t.meta["n_samples"] == n and t.meta["duration"] == 10.0
    assert t.meta["anr_linear"] == pytest.approx(125.0) and t.meta["anr_db_paper_ln"] == pytest.approx(
        48.283, abs=1e-3
    )
    assert (
        "spec" not in t.meta["assumptions"]
        and "the mode-signature paper does not state" in t.meta["assumptions"]
    )
    np.testing.assert_array_equal(rec.combined_reference, rec.r[:, 0] + 0.5 * z[0])
    assert rec.summary.startswith("simulated 200 samples: mode 3, tau 140 samples")


def test_drawn_inputs_and_h0():
    """Without mode, code phase or carrier phase the record takes trial 0's draws; H0 has no signature."""
    draw = draw_trial(5, 0, 40, 3, 31, 20)
    rec = simulate_record(RecordConfig(V1, duration=2.0, seed=5, signature=False, theta=0.25))
    assert rec.table.meta["mode"] == draw.mode + 1 and rec.table.meta["tau"] == draw.tau
    assert rec.table.meta["theta"] == 0.25 and rec.table.meta["signature"] is False
    assert not rec.z.any()


def test_zero_amplitude_has_no_anr_in_db():
    rec = simulate_record(RecordConfig(Vehicle1D(a_sig=0.0), duration=1.0))
    meta = rec.table.meta
    assert meta["anr_linear"] == 0.0 and meta["anr_db_log10"] is None and meta["anr_db_paper_ln"] is None
    assert rec.summary.endswith("(ANR 0)")


def test_2d_record_and_its_metadata():
    rec = simulate_record(RecordConfig(V2, mode=2, tau=33, duration=3.0, anr_pair=4))
    t = rec.table
    assert t.columns == COLUMNS_2D and len(t.rows) == 60 and rec.two_d
    assert t.meta["anr_pair"] == 4 and t.meta["seed_anr_pair_labels"] == [101.3, 129.2]
    assert t.meta["anr_range_db_paper_ln"] == pytest.approx(129.2) and t.meta["start"] == [70.0, -20.0]
    rng = np.array([row[2] for row in t.rows])
    assert np.allclose(rng, np.hypot(rec.x[:, 0], rec.x[:, 2]), atol=0.01)
    no_pair = simulate_record(RecordConfig(Vehicle2D(R_range=1e-3), duration=1.0))
    assert no_pair.table.meta["anr_pair"] is None and no_pair.table.meta["seed_anr_pair_labels"] is None


@pytest.mark.parametrize(
    ("vehicle", "field"),
    [
        (Vehicle2D(R_range=100.0, R_bearing=1e-3), "R_range"),  # 10 sigma = 100 m: more than the range
        (Vehicle2D(start=(-5.0, -5.0)), "start"),  # the path passes 5 mm from the radar
        (Vehicle2D(K=(1e9, 1e9)), "K"),  # unstable loop
        (Vehicle1D(K=(1e9, 1e9)), "K"),
        (Vehicle1D(a_sig=1e307), "a_sig"),  # a stable loop driven to overflow
    ],
)
def test_records_that_cannot_be_simulated(vehicle, field):
    with pytest.raises(ConfigError) as exc:
        simulate_record(RecordConfig(vehicle, duration=20.0))
    assert exc.value.field == field


def test_a_negative_measured_range_is_refused(monkeypatch):
    """Beyond 10 range-noise standard deviations a range <= 0 takes a > 10 sigma draw: forced here."""
    from dataclasses import replace

    from motionsig_cli.modesig import lmp1d

    def draw(*args, **kwargs):
        d = draw_trial(*args, **kwargs)
        v = d.v.copy()
        v[5, 0] = -1e6
        return replace(d, v=v)

    monkeypatch.setattr(lmp1d, "draw_trial", draw)
    with pytest.raises(ConfigError, match=r"measured range <= 0 \(t = 0.25 s\)") as exc:
        simulate_record(RecordConfig(V2, duration=1.0))
    assert exc.value.field == "R_range"
