"""Ground truth of turns from a track angle, and the scoring of declarations (maneuver.turn_truth)."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.maneuver.turn_truth import (
    Turn,
    TurnScore,
    TurnTruth,
    TurnTruthConfig,
    score_declarations,
    turn_intervals,
)
from tests.adsb import FLIGHTS, load_flight, load_radar

# --- synthetic tracks ---------------------------------------------------------------------------------

# the truth: right at 3 deg/s from 100 s for 30 s (90 deg), left at 1.5 deg/s from 250 s for 40 s
TURNS = ((100.0, 130.0, 3.0), (250.0, 290.0, -1.5))
T_END = 400.0


def _track(t):
    """The true track angle of TURNS (coordinated turns: a constant rate, steps of the rate)."""
    ang = np.full(t.shape, 350.0)
    for a, b, w in TURNS:
        ang += w * np.clip(t - a, 0.0, b - a)
    return ang


def _recording(seed, quantum=1.0, dt=(0.2, 0.8)):
    """An ADS-B-like recording of TURNS: irregular times (uniform Δt), angles quantised to ``quantum``
    and wrapped to [0, 360), 5 % exact duplicate rows and 10 % stale rows (the previous angle under a
    new timestamp). Returns t, track and the longest stale hold in seconds."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(*dt, size=int(T_END / np.mean(dt)) + 10))
    t = t[t < T_END]
    ang = np.mod(np.round(_track(t) / quantum) * quantum, 360.0)
    stale = rng.uniform(size=t.size) < 0.10
    stale[0] = False
    hold, longest = 0.0, 0.0
    for i in range(1, t.size):
        if stale[i]:
            ang[i] = ang[i - 1]
            hold += t[i] - t[i - 1]
            longest = max(longest, hold)
        else:
            hold = 0.0
    dup = np.flatnonzero(rng.uniform(size=t.size) < 0.05)
    t = np.insert(t, dup, t[dup])
    ang = np.insert(ang, dup, ang[dup])
    return t, ang, longest


@pytest.mark.parametrize(("seed", "quantum"), [(1, 1.0), (2, 0.1), (3, 1.0)])
def test_coordinated_turns_are_recovered(seed, quantum):
    t, ang, hold = _recording(seed, quantum)
    truth = turn_intervals(t, ang)
    h = truth.config.smoothing_s / 2.0
    # tolerance on each end: a rate step at t0 seen through the centred least-squares window of
    # half-width h gives the slope w (1/2 - 3z/4 + z^3/4), z = (t0 - c) / h; it crosses the 1 deg/s
    # threshold at |z| = 0.23 for w = 1.5 and for w = 3 (on opposite sides), so within 0.23 h of t0;
    # plus one sampling interval (0.8 s) and the longest stale hold (a delay of the reported angle)
    tol = 0.25 * h + 0.8 + hold + 0.5
    assert len(truth.turns) == 2, truth.turns
    for got, (a, b, w) in zip(truth.turns, TURNS, strict=True):
        assert abs(got.start_s - a) <= tol and abs(got.end_s - b) <= tol, (got, a, b, tol)
        # the run's edges hold slopes between the threshold and w: the mean is within 10 %
        assert got.mean_rate_deg_s == pytest.approx(w, rel=0.10)
    # straight flight: everything but the turns and a window's width at each of their ends
    straight_expected = T_END - sum(b - a + 2 * truth.config.smoothing_s for a, b, _ in TURNS)
    assert truth.straight_s >= straight_expected - 5.0
    assert truth.in_straight(np.array([50.0, 200.0, 350.0])).all()
    assert not truth.in_straight(np.array([115.0, 270.0])).any()


def test_rate_estimate_is_a_fit_not_a_difference():
    # a straight leg quantised to 1 deg at 0.5 s: differences jump by 2 deg/s, the fit stays calm
    t = np.arange(0.0, 120.0, 0.5)
    ang = np.round(45.0 + 0.05 * t)  # 0.05 deg/s drift
    assert np.max(np.abs(np.diff(ang) / np.diff(t))) == pytest.approx(2.0)
    truth = turn_intervals(t, ang)
    assert truth.turns == ()
    assert np.nanmax(np.abs(truth.rate_deg_s)) < truth.config.straight_threshold_deg_s
    assert truth.straight_s == pytest.approx(t[-1] - t[0])


def test_turn_across_north_and_s_turn():
    t = np.arange(0.0, 200.0, 1.0)
    # right from 340 through north to 70 (3 deg/s, 30 s), then straight, then left 2 deg/s and right
    # 2 deg/s (an S-turn): three turns, signs +, -, +
    rate = np.zeros(t.size)
    rate[(t >= 20) & (t < 50)] = 3.0
    rate[(t >= 100) & (t < 130)] = -2.0
    rate[(t >= 130) & (t < 160)] = 2.0
    ang = np.mod(340.0 + np.r_[0.0, np.cumsum(rate[:-1])], 360.0)
    truth = turn_intervals(t, ang)
    assert [round(x.mean_rate_deg_s) for x in truth.turns] == [3, -2, 2]
    assert truth.turns[1].end_s < truth.turns[2].start_s


def test_no_rate_across_a_gap():
    t = np.r_[np.arange(0.0, 110.0, 5.0), np.arange(170.0, 300.0, 5.0)]  # 60 s without reports
    ang = _track(t + 10.0)  # the first turn runs 90..120 s: the gap cuts its end
    truth = turn_intervals(t, ang)
    for x in truth.turns:
        assert not (x.start_s < 140.0 < x.end_s), x  # nothing spans the gap
    assert all(b <= 105.0 or a >= 170.0 for a, b in truth.straight)
    # the samples at the gap's edges have no rate (one neighbour within the window: 2 samples)
    finite = np.isfinite(truth.rate_deg_s)
    assert not finite[[0, 21, 22, -1]].any() and finite[1:21].all() and finite[23:-1].all()


def test_sparse_reports_widen_the_window():
    # one report every 6-12 s: fewer than 3 samples in 10 s, so the window reaches the neighbours
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(6.0, 12.0, size=60))
    t = t[t < T_END]
    truth = turn_intervals(t, _track(t))
    assert np.isfinite(truth.rate_deg_s[1:-1]).all()
    assert [np.sign(x.mean_rate_deg_s) for x in truth.turns] == [1.0, -1.0]


def test_a_single_stray_value_is_no_turn():
    t = np.arange(0.0, 100.0, 5.0)
    ang = np.full(t.size, 120.0)
    ang[8] = 300.0  # a resampled feed's stray value, 180 deg off
    truth = turn_intervals(t, ang)
    assert truth.turns == ()
    assert truth.t_s.size == t.size - 1


def test_implausible_rates_with_speed_are_dropped():
    # the feed interpolated 352 -> 2 deg the long way round in 25 s (15 deg/s at 180 m/s: 60 deg of
    # bank gives 5.4 deg/s); without the speed it is a turn, with it no rate there
    t = np.arange(0.0, 120.0, 1.0)
    ang = np.where(t < 40, 352.0, np.where(t < 65, 352.0 - 14.0 * (t - 39), 2.0))
    ang = np.mod(ang, 360.0)
    assert len(turn_intervals(t, ang).turns) == 1
    truth = turn_intervals(t, ang, speed_mps=np.full(t.size, 180.0))
    assert truth.turns == ()
    assert np.isnan(truth.rate_deg_s[(t > 45) & (t < 60)]).all()


def test_slow_rows_are_skipped():
    t = np.arange(0.0, 100.0, 1.0)
    ang = np.where(t < 50, np.mod(7.0 * t, 360.0), 90.0)  # taxiing in circles, then the runway
    v = np.where(t < 50, 5.0, 60.0)
    truth = turn_intervals(t, ang, speed_mps=v, min_speed_mps=25.0)
    assert truth.turns == () and truth.t_s.min() >= 50.0


def test_bad_arguments():
    t = np.arange(10.0)
    with pytest.raises(ConfigError, match="straight_threshold_deg_s"):
        turn_intervals(t, t, straight_threshold_deg_s=1.5)
    with pytest.raises(ConfigError, match="smoothing_s"):
        turn_intervals(t, t, smoothing_s=0.0)
    with pytest.raises(ConfigError, match="t_s"):
        turn_intervals(t[::-1], t)
    with pytest.raises(ConfigError, match="track_deg"):
        turn_intervals(t, t[:-1])
    with pytest.raises(ConfigError, match="end_s"):
        Turn(10.0, 5.0, 1.0)
    with pytest.raises(ConfigError, match="max_bank_deg"):
        TurnTruthConfig(max_bank_deg=90.0)
    with pytest.raises(ConfigError, match="hits"):
        TurnScore(-1, 0, 0, 0, 0.0, math.nan)


# --- scoring ------------------------------------------------------------------------------------------

STRAIGHT = [(0.0, 95.0), (140.0, 245.0), (300.0, 3600.0)]
TWO = [Turn(100.0, 130.0, 3.0), Turn(250.0, 290.0, -1.5)]


def test_hit_window_ends_are_inclusive():
    s = score_declarations([95.0, 265.0], TWO, STRAIGHT)
    assert (s.hits, s.misses, s.false_alarms, s.delays_s) == (2, 0, 0, (-5.0, 15.0))
    s = score_declarations([94.99, 265.01], TWO, STRAIGHT)
    assert (s.hits, s.misses) == (0, 2)
    # 94.99 lies in straight flight: a false alarm; 265.01 lies in the turn: ignored
    assert (s.false_alarms, s.ignored) == (1, 1)


def test_one_declaration_matches_one_turn():
    close = [Turn(100.0, 112.0, 2.0), Turn(110.0, 125.0, -2.0)]
    s = score_declarations([108.0], close, STRAIGHT)
    assert (s.hits, s.misses, s.hit_turns) == (1, 1, (0,))
    # two declarations in the overlap of both windows: both turns hit, earliest to the first
    s = score_declarations([112.0, 108.0], close, STRAIGHT)
    assert (s.hits, s.misses, s.hit_turns, s.delays_s) == (2, 0, (0, 1), (8.0, 2.0))


def test_declarations_in_turns_are_not_false_alarms():
    s = score_declarations([101.0, 105.0, 120.0, 125.0, 500.0, 1000.0], TWO, STRAIGHT)
    assert (s.hits, s.misses, s.false_alarms, s.ignored) == (1, 1, 2, 3)
    hours = sum(b - a for a, b in STRAIGHT) / 3600.0
    assert s.straight_hours == pytest.approx(hours)
    assert s.false_alarms_per_hour == pytest.approx(2 / hours)
    assert s.p_detect == 0.5


def test_scoring_edge_cases():
    s = score_declarations([], TWO, STRAIGHT)
    assert (s.hits, s.misses, s.false_alarms, s.false_alarms_per_hour) == (0, 2, 0, 0.0)
    s = score_declarations([10.0], [], [])
    assert (s.false_alarms, s.ignored, s.straight_hours) == (0, 1, 0.0)
    assert math.isnan(s.false_alarms_per_hour) and math.isnan(s.p_detect)
    with pytest.raises(ConfigError, match="early_s"):
        score_declarations([1.0], TWO, STRAIGHT, early_s=-1.0)
    with pytest.raises(ConfigError, match="declared_t"):
        score_declarations([math.nan], TWO, STRAIGHT)
    with pytest.raises(ConfigError, match="straight"):
        score_declarations([1.0], TWO)
    with pytest.raises(ConfigError, match="straight"):
        score_declarations([1.0], TWO, [(5.0, 1.0)])


def test_scoring_takes_a_turn_truth():
    t, ang, _ = _recording(4)
    truth = turn_intervals(t, ang)
    onsets = [x.start_s + 2.0 for x in truth.turns] + [50.0]
    s = score_declarations(onsets, truth)
    assert (s.hits, s.misses, s.false_alarms) == (2, 0, 1)
    assert s.straight_hours == pytest.approx(truth.straight_s / 3600.0)
    assert isinstance(truth, TurnTruth) and not truth.rate_deg_s.flags.writeable


# --- the real recordings ------------------------------------------------------------------------------

# turns per flight (airborne rows: ground speed >= 25 m/s). The counts were checked against plots of the
# track angle with the intervals drawn: noisy_landing's 4 (two right turns onto the approach, two left
# at the end) and raw_rs1090_cdg's 2 (the left turns of the climb-out after a straight departure) are
# the visible turns one by one. The calibration, airbus_tree and texas counts are pinned as found
# (regression values): on the plots each interval lies on a visible change of track, but they are not
# a count by eye: a long turn near 1 deg/s splits into pieces (airbus_tree's first left turn, ~1.1
# deg/s, is 4), texas's heading changes across gaps > 15 s are not counted, and their resampled tracks
# hold stray values and interpolation the long way round north, which the spike and bank checks drop.
TURNS_PER_FLIGHT = {
    "gaps_airbus_tree": 22,
    "raw_rs1090_cdg": 2,
    "noisy_landing": 4,
    "turns_calibration_cardiff": 71,  # the byte-wrapped track column repaired (tests/adsb.py)
    "sparse_texas_longhorn": 14,
}


def _truth(name):
    f = load_flight(name)
    return f, turn_intervals(f["t_s"], f["track_deg"], speed_mps=f["gs_mps"], min_speed_mps=25.0)


@pytest.mark.parametrize("name", FLIGHTS)
def test_turns_on_the_real_recordings(name):
    f, truth = _truth(name)
    print(name, len(truth.turns), "turns,", f"{truth.straight_s / 3600:.2f} h straight")
    assert len(truth.turns) == TURNS_PER_FLIGHT[name]
    assert all(x.duration_s >= 10.0 and abs(x.mean_rate_deg_s) > 1.0 for x in truth.turns)
    span = f["t_s"][-1] - f["t_s"][0]
    assert 0.0 < truth.straight_s < span
    # no turn and no straight interval spans a gap of more than 15 s between the samples used
    big = np.flatnonzero(np.diff(truth.t_s) > truth.config.max_gap_s)
    for lo, hi in zip(truth.t_s[big], truth.t_s[big + 1], strict=True):
        assert not any(x.start_s < hi and x.end_s > lo for x in truth.turns)
        assert not any(a < hi and b > lo for a, b in truth.straight)


def test_loader_keeps_the_recording_as_recorded():
    raw = load_flight("raw_rs1090_cdg")
    n = raw["t_s"].size
    assert n == 6910 and raw["t_s"][0] == 0.0 and np.all(np.diff(raw["t_s"]) >= 0)
    # positions and velocities on separate message rows
    has_pos, has_vel = np.isfinite(raw["lat"]), np.isfinite(raw["track_deg"])
    assert has_pos.sum() == 3919 and (has_vel & ~has_pos).sum() > 2000
    rows = np.c_[raw["t_s"], raw["lat"], raw["lon"], raw["track_deg"], raw["gs_mps"]]
    assert len({tuple(r) for r in rows.round(6).tolist()}) < n  # exact duplicates kept
    land = load_flight("noisy_landing")
    same = (np.diff(land["lat"]) == 0) & (np.diff(land["lon"]) == 0)
    assert same.sum() == 167  # stale positions kept
    assert 60.0 < np.nanmedian(land["gs_mps"]) < 130.0  # 250 kt -> m/s, an approach
    assert land["alt_m"][0] == pytest.approx(14150 * 0.3048)


def test_radar_export_matches_its_trajectory():
    pymap3d = pytest.importorskip("pymap3d")
    meta, radar = load_radar()
    site = meta["sensor"]
    assert meta["sigma_range_nm"] == 0.03 and meta["sigma_bearing_deg"] == 0.08
    f = load_flight("turns_calibration_cardiff")
    ts = radar["t_s"] + float(radar["t0_unix_s"] - f["t0_unix_s"])  # scan times on the flight's clock
    # scans every 4 s with jitter: consecutive scans 4 s apart (+-0.6 s) or a multiple for misses
    d = np.diff(ts)
    k = np.round(d / 4.0)
    assert np.all(np.abs(d - 4.0 * k) <= 0.6 + 1e-6) and np.all(k >= 1)
    x, y, z = pymap3d.geodetic2ecef(f["lat"], f["lon"], f["alt_m"])
    p = [np.interp(ts, f["t_s"], c) for c in (x, y, z)]
    az, _, srange = pymap3d.ecef2aer(*p, site["latitude"], site["longitude"], site["altitude_m"])
    dr = radar["range_nm"] - srange / 1852.0
    db = np.mod(radar["bearing_deg"] - az + 180.0, 360.0) - 180.0
    n = dr.size
    assert 20.0 <= np.median(radar["range_nm"]) <= 60.0
    # the noise is what the header says: sample std within 3 standard errors (~ sigma / sqrt(2n))
    for resid, sigma in ((dr, 0.03), (db, 0.08)):
        assert abs(resid.mean()) < 4 * sigma / math.sqrt(n)
        assert abs(resid.std() / sigma - 1.0) < 3.0 / math.sqrt(2 * n) + 0.01
