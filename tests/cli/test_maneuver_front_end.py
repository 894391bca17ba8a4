"""``motionsig maneuver --front-end ebpsk``: the trackers on the EBPSK radar's measurements, the front-end
table, figures, and bad input (one line naming the option, exit 2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.cli.helpers import one_line_error, run, table

SMALL = ("--front-end", "ebpsk", "--runs", "3", "--scans", "60")


def test_ebpsk_monte_carlo_runs_every_method_with_missed_scans(capsys, tmp_path):
    png = tmp_path / "f.png"
    rc, out, err = run(capsys, "maneuver", *SMALL, "--method", "all", "--view", "summary", "--plot", str(png))
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.meta["sigma"] == [100.0, 200.0] and t.meta["front_end"]["level"] == "detector"
    p = t.meta["front_end"]["p_t_W"]
    assert len(p) == 2 and p[0] == pytest.approx(4 * p[1], rel=0.05)  # half the σ: four times the power
    assert [r[1] for r in t.rows] == ["imm", "glr", "mlr", "cv"] * 2
    assert png.stat().st_size > 0 and "maneuver: σ=100 imm RMS" in err


def test_samples_level_runs_and_p_t_gives_the_delivered_sigma(capsys, tmp_path):
    rc, out, err = run(capsys, "maneuver", "--front-end", "ebpsk", "--level", "samples", "--runs", "1",
                       "--scans", "12", "--p-t", "1e9", "--method", "imm,cv")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    (s,) = t.meta["sigma"]
    assert t.meta["front_end"]["p_t_W"] == 1e9 and t.meta["front_end"]["level"] == "samples"
    assert 1.0 < s < 200.0  # the median σ of 12 scans ~200 km away at 1 GW (≈ 75 m per axis)
    assert all(math.isfinite(float(r[t.columns.index("rms_pos")])) for r in t.rows)


def test_front_end_view_tabulates_sigma_and_the_powers_for_the_papers_values(capsys, tmp_path):
    png = tmp_path / "fe.png"
    rc, out, err = run(capsys, "maneuver", "--front-end", "ebpsk", "--view", "front-end", "--plot", str(png))
    assert rc == 0, err
    t = table(out, tmp_path)
    assert [r[0] for r in t.rows] == ["cruise", "turn 1", "turn 2", "after", "track"]
    c = t.columns
    for r in t.rows:
        assert float(r[c.index("p_t_W_for_100")]) == pytest.approx(
            4 * float(r[c.index("p_t_W_for_200")]), rel=0.02
        )
        assert float(r[c.index("sigma_pos_m")]) >= float(r[c.index("sigma_cross_m")]) / math.sqrt(2) - 1e-6
    pd = np.array([float(r[c.index("pd")]) for r in t.rows])
    assert pd[3] < 0.9 < pd[0]  # P_D < 1 at the far end of the literal track (530 km), ≈ 1 in the cruise
    assert png.stat().st_size > 0


def test_network_view_compares_the_nodes_with_the_single_radar(capsys, tmp_path):
    """--view network: per phase, the nodes' RMS position error (a Monte Carlo of WLS fixes) beside the single
    radar's σ at the same power; --nodes places them (here three nodes around the first 60 scans)."""
    rc, out, err = run(capsys, "maneuver", "--front-end", "ebpsk", "--view", "network", "--runs", "20",
                       "--scans", "60", "--nodes", "-80000,40000;80000,40000;0,-60000")  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    c = t.columns
    assert t.meta["network"]["nodes_m"] == [[-80000.0, 40000.0], [80000.0, 40000.0], [0.0, -60000.0]]
    track = t.rows[-1]
    assert track[0] == "track"
    assert float(track[c.index("single_median_sigma_pos_m")]) == pytest.approx(100.0)
    assert 0 < float(track[c.index("rms_pos_m")]) < 10.0
    assert "3 nodes" in err and "RMS position error" in err


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (("--view", "network"), "--view"),
        (("--front-end", "ebpsk", "--nodes", "0,0;1,1;2,2"), "--nodes"),
        (("--front-end", "ebpsk", "--view", "network", "--nodes", "0,0;1,x"), "--nodes"),
        (("--front-end", "ebpsk", "--view", "network", "--nodes", "0,0;1,1"), "--nodes"),
        (("--front-end", "ebpsk", "--view", "network", "--nodes", "1,2,3;4,5,6;7,8,9"), "--nodes"),
        (("--front-end", "ebpsk", "--view", "network", "--plot", "x.png"), "--plot"),
        (("--p-t", "1e6"), "--p-t"),
        (("--level", "samples"), "--level"),
        (("--view", "front-end"), "--view"),
        (("--front-end", "ebpsk", "--pri", "1e-3"), "--pri"),
        (("--front-end", "ebpsk", "--radar-position", "0,0"), "--radar-position"),
        (("--front-end", "ebpsk", "--radar-position", "1,2,3"), "--radar-position"),
        (("--front-end", "ebpsk", "--beamwidth", "0"), "--beamwidth"),
        (("--front-end", "ebpsk", "--p-t", "-5"), "--p-t"),
        (("--front-end", "ebpsk", "--gain-db", "200"), "--gain-db"),
        (("--front-end", "ebpsk", "--pfa", "2"), "--pfa"),
        (("--front-end", "ebpsk", "--p-t", "1e9", "--sigma", "100"), "--sigma"),
        (("--front-end", "ebpsk", "--sigma", "1e-3"), "--sigma"),
        (("--front-end", "ebpsk", "--input", "x.csv"), "--front-end"),
    ],
)
def test_bad_front_end_input_is_one_line_naming_the_option(capsys, args, option):
    err = one_line_error(capsys, "maneuver", "--runs", "2", "--scans", "30", *args)
    assert option in err
