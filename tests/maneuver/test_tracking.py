"""track_positions (the trackers on a track given as arrays) against the command's own path on the same
record, the batch path, and the per-row noise forms; imm_filter on one (N, m) record."""

from __future__ import annotations

import numpy as np
import pytest

from motionsig_cli import ConfigError, TrackerConfig, imm_filter, imm_models, track_positions, two_point_init
from motionsig_cli.maneuver.record import read_track_record
from motionsig_cli.maneuver.record_tracking import track_record
from motionsig_cli.models.motion import H_POS6
from motionsig_cli.tables import Table

METHODS = ("imm", "glr", "mlr", "cv")


def _track(seed: int = 1, n: int = 60) -> tuple[np.ndarray, np.ndarray]:
    """A target at (300, 50) m/s that accelerates at 3 m/s² in y from t = 30 s, σ = 50 m; row 10 missed."""
    rng = np.random.default_rng(seed)
    t = np.arange(float(n))
    truth = np.stack([300 * t, 50 * t + 1.5 * np.maximum(t - 30, 0) ** 2], axis=1)
    z = truth + 50 * rng.standard_normal(truth.shape)
    z[10] = np.nan
    return t, z


@pytest.mark.parametrize("method", METHODS)
def test_equals_the_command_path_on_the_same_record(method: str) -> None:
    # oracle: maneuver/record.py's track_record on the same rows read as a table (motionsig maneuver --input)
    t, z = _track()
    res = track_positions(t, z, 50.0, method=method)
    rows = [(float(tt), *("" if np.isnan(v) else float(v) for v in zz)) for tt, zz in zip(t, z, strict=True)]
    rec = track_record(read_track_record(Table(columns=("time", "x", "y"), rows=rows)), [method],
                       TrackerConfig(), sigma=50.0, consistency=None)  # fmt: skip
    state = np.array([r[4:10] for r in rec.table.rows], float)
    np.testing.assert_allclose(state, res.state, rtol=1e-11, atol=1e-9)  # per-step Δt = T: to rounding
    assert np.array_equal([r[3] for r in rec.table.rows], res.measured)
    if method in ("glr", "mlr"):
        declared = np.array([r[13] for r in rec.table.rows])
        assert np.array_equal(declared, res.detected)
        onsets = [r[14] for r in rec.table.rows if r[13]]
        assert onsets == [int(v) + 3 for v in res.onset[res.detected]]  # output row 0 is scan 3
    assert res.t[0] == 2.0 and res.T == 1.0


@pytest.mark.parametrize("method", METHODS)
def test_a_batch_row_equals_that_track_alone(method: str) -> None:
    tracks = [_track(seed)[1] for seed in (1, 2, 3)]
    t = _track()[0]
    batch = track_positions(t, np.stack(tracks), 50.0, method=method)
    assert batch.state.shape == (3, 58, 6)
    for i, z in enumerate(tracks):
        one = track_positions(t, z, 50.0, method=method)
        np.testing.assert_allclose(batch.state[i], one.state, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("method", METHODS)
def test_constant_per_row_sigma_and_cov_equal_the_scalar(method: str) -> None:
    t, z = _track()
    ref = track_positions(t, z, 50.0, method=method)
    per_row = track_positions(t, z, np.full(t.size, 50.0), method=method)
    cov = track_positions(t, z, cov=np.broadcast_to(2500.0 * np.eye(2), (t.size, 2, 2)), method=method)
    for other in (per_row, cov):
        np.testing.assert_allclose(other.state, ref.state, rtol=1e-9, atol=1e-6)


def test_gaps_in_the_times_are_missed_scans() -> None:
    t, z = _track()
    keep = np.ones(t.size, bool)
    keep[[20, 21]] = False
    with_gap = track_positions(t[keep], z[keep], 50.0)
    z2 = z.copy()
    z2[[20, 21]] = np.nan
    assert np.array_equal(with_gap.state, track_positions(t, z2, 50.0).state)
    assert with_gap.row[18] == -1 and not with_gap.measured[18]


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"sigma": -1.0}, "sigma"),
        ({"sigma": np.ones(5)}, "sigma"),
        ({"sigma": 1.0, "method": "kalman"}, "method"),
        ({"sigma": 1.0, "T": 0.3}, "times"),
        ({"cov": np.ones((2, 2))}, "cov"),
        ({}, "sigma"),
    ],
)
def test_bad_arguments_name_their_field(kwargs: dict, field: str) -> None:
    t, z = _track()
    with pytest.raises(ConfigError) as exc:
        track_positions(t, z, **kwargs)
    assert exc.value.field == field


def test_imm_filter_takes_one_record_and_a_scalar_R() -> None:
    # the old code refused z of shape (N, 2) ("z must be (runs, scans, m)") and a scalar R
    z = _track()[1][:10]
    x0, P0 = two_point_init(z[0], z[1], 1.0, 50.0)
    one = imm_filter(z[2:], H_POS6, 2500.0, imm_models(1.0), x0, P0, keep_P=True)
    ref = imm_filter(z[None, 2:], H_POS6, 2500.0 * np.eye(2), imm_models(1.0), x0[None], P0)
    assert one.x.shape == (8, 6) and one.P is not None and one.P.shape == (8, 6, 6)
    assert np.array_equal(one.x, ref.x[0]) and np.array_equal(one.log_mu, ref.log_mu[0])


def test_imm_filter_takes_one_record_with_per_scan_R() -> None:
    z = _track()[1][:10]
    x0, P0 = two_point_init(z[0], z[1], 1.0, 50.0)
    R = np.broadcast_to(2500.0 * np.eye(2), (8, 2, 2))
    one = imm_filter(z[2:], H_POS6, R, imm_models(1.0), x0, P0)
    ref = imm_filter(z[None, 2:], H_POS6, R[None], imm_models(1.0), x0[None], P0)
    assert np.array_equal(one.x, ref.x[0])


@pytest.mark.parametrize("method", METHODS)
def test_irregular_times_are_steps_at_their_own_times_as_the_command_tracks_them(method: str) -> None:
    """Times off every grid (0.3–1.7 s apart): track_positions runs each row at its own time and equals the
    command's path on the same rows (record_tracking without the checks) to rounding."""
    rng = np.random.default_rng(12)
    t = np.cumsum(rng.uniform(0.3, 1.7, 150))
    z = np.stack([120.0 * t, 0.5 * 2.0 * np.maximum(t - 80.0, 0) ** 2], axis=1) + 20 * rng.standard_normal(
        (150, 2)
    )
    res = track_positions(t, z, 20.0, method=method)
    assert res.t.tolist() == t[2:].tolist() and res.state.shape == (148, 6)
    rows = [(float(a), float(b), float(c)) for a, (b, c) in zip(t, z, strict=True)]
    rec = track_record(read_track_record(Table(columns=("time", "x", "y"), rows=rows)), [method],
                       TrackerConfig(), sigma=20.0, consistency=None)  # fmt: skip
    state = np.array([r[4:10] for r in rec.table.rows], float)
    np.testing.assert_allclose(state, res.state, rtol=1e-10, atol=1e-8)
