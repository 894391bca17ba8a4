"""`motionsig encode ebpsk`: the waveform table, its metadata, the BER table, plots and one-line errors.

The waveform is checked against the definition computed here with plain numpy (not the module's code);
the filter output against scipy's lfilter with the coefficients the metadata records.
"""

import math

import numpy as np
import pytest
from scipy import signal as sp_signal

from tests.cli.helpers import one_line_error, run, table


def test_waveform_table_matches_definition(capsys, tmp_path):
    rc, out, err = run(capsys, "encode", "ebpsk", "--bits", "0110100")
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.columns == ("sample", "t", "bit", "symbol", "x", "y")
    n = t.numeric("sample", integer=True)
    assert len(n) == 7 * 70
    bits = np.array([0, 1, 1, 0, 1, 0, 0])
    np.testing.assert_array_equal(t.numeric("symbol", integer=True), n // 70)
    np.testing.assert_array_equal(t.numeric("bit", integer=True), bits[n // 70])
    np.testing.assert_allclose(t.numeric("t"), n / 1e9)
    jump = (bits[n // 70] == 1) & (n % 70 < 20)  # first K = 2 cycles of 10 samples
    np.testing.assert_allclose(t.numeric("x"), np.sin(2 * np.pi * 0.1 * n + np.pi * jump), atol=1e-9)
    b, a = np.array(t.meta["filter_b"]), np.array(t.meta["filter_a"])
    np.testing.assert_allclose(t.numeric("y"), sp_signal.lfilter(b, a, t.numeric("x")), atol=1e-9)
    assert t.meta["f_carrier"] == 10e9 and t.meta["K"] == 2 and t.meta["N"] == 7
    assert t.meta["impact_ratio"] > 10
    assert "impact ratio" in err


def test_code_chips_and_plot(capsys, tmp_path):
    png = tmp_path / "w.png"
    rc, out, err = run(capsys, "encode", "ebpsk", "--code", "gold:45,75:1", "--plot", str(png), "-q")
    assert rc == 0, err
    t = table(out, tmp_path)
    assert len(t.rows) == 31 * 70
    rc, gold, _ = run(capsys, "encode", "gold", "--poly1", "45", "--poly2", "75", "--index", "-2")
    chips = table(gold, tmp_path, "g.csv").numeric("value", integer=True)
    per_symbol = t.numeric("bit", integer=True)[::70]
    np.testing.assert_array_equal(per_symbol, chips)
    assert png.stat().st_size > 10_000


def test_ber_table(capsys, tmp_path):
    png = tmp_path / "ber.png"
    args = ("encode", "ebpsk", "--ber", "--ebn0", "8,16", "--trials", "4", "--bits-per-trial", "500")
    rc, out, err = run(capsys, *args, "--plot", str(png), "--workers", "1")
    assert rc == 0, err
    t = table(out, tmp_path)
    cols = ("ebn0_db", "bits", "errors", "ber", "se", "coherent_bound", "closed_form", "threshold")
    assert t.columns == cols
    assert t.meta["receiver"] == "differential" and t.meta["span"] == 3
    ber, se, bound = t.numeric("ber"), t.numeric("se"), t.numeric("coherent_bound")
    closed = t.numeric("closed_form")
    assert np.all(np.abs(ber - closed) < 4 * np.sqrt(closed * (1 - closed) / 2000) + 1e-12)
    assert list(t.numeric("bits", integer=True)) == [2000, 2000]
    np.testing.assert_allclose(se, np.sqrt(ber * (1 - ber) / 2000))
    assert ber[1] < ber[0] and np.all(ber >= bound - 4 * np.sqrt(bound * (1 - bound) / 2000))
    assert bound[0] == pytest.approx(0.5 * math.erfc(math.sqrt(4 / 7 * 10**0.8) / math.sqrt(2)))
    assert t.meta["rho"] == pytest.approx(3 / 7)
    assert png.stat().st_size > 10_000
    # same output with 2 workers and a fixed seed
    rc, out2, _ = run(capsys, *args, "--workers", "2")
    assert out2 == out


def test_ber_receivers(capsys, tmp_path):
    """--receiver picks the registered receiver; the impacting ones calibrate a threshold, record their
    filter, and have no closed form; the earlier default stays reachable by name."""
    args = ("encode", "ebpsk", "--ber", "--ebn0", "10", "--trials", "2", "--bits-per-trial", "500", "-q")
    seen = {}
    for name in ("differential", "matched", "impacting", "impacting-assumed"):
        rc, out, err = run(capsys, *args, "--receiver", name)
        assert rc == 0, err
        t = table(out, tmp_path, f"{name}.csv")
        assert t.meta["receiver"] == name
        seen[name] = t
    assert seen["impacting"].meta["filter_pole_radius"] == pytest.approx(math.exp(-1 / 20))
    assert seen["impacting-assumed"].meta["filter_pole_radius"] == 0.93
    assert seen["impacting"].numeric("threshold")[0] > 0
    assert math.isnan(seen["impacting"].numeric("closed_form")[0])
    assert seen["matched"].numeric("closed_form")[0] == seen["matched"].numeric("coherent_bound")[0]
    assert seen["differential"].numeric("threshold")[0] == 0


@pytest.mark.parametrize(
    "args, option",
    [
        (("--K", "7"), "--K"),
        (("--N", "0"), "--N"),
        (("--fs", "1.5e8"), "--fs"),
        (("--bits", ""), "--bits"),
        (("--bits", "0120"), "--bits"),
        (("--theta", "0"), "--theta"),
        (("--code", "nope"), "--code"),
        (("--bits", "01", "--code", "gps:1"), "--bits"),
        (("--ebn0", "3"), "--ebn0"),
        (("--ber", "--bits", "01"), "--bits"),
        (("--ber", "--ebn0", "3,x"), "--ebn0"),
        (("--ber", "--trials", "0"), "--trials"),
        (("--ber", "--threshold", "-1"), "--threshold"),
        (("--ber", "--receiver", "impacting", "--threshold", "-1"), "--threshold"),
        (("--ber", "--span", "2"), "--span"),
        (("--ber", "--receiver", "matched", "--span", "3"), "--span"),
        (("--ber", "--q", "3"), "--q"),
        (("--ber", "--receiver", "impacting", "--q", "0.5"), "--q"),
        (("--ber", "--statistic", "energy"), "--statistic"),
        (("--ber", "--receiver", "coherent"), "--receiver"),
        (("--span", "3"), "--span"),
        (("--pole-radius", "1"), "--pole-radius"),
    ],
)
def test_bad_input_is_one_line(capsys, args, option):
    err = one_line_error(capsys, "encode", "ebpsk", *args)
    assert option in err


def test_the_command_layer_lists_the_registered_receivers():
    """The command module spells out the receivers without importing NumPy: they must be the registry's."""
    from motionsig_cli.cli import encode as cli
    from motionsig_cli.signals.ebpsk import DEFAULT_RECEIVER, DEFAULT_SPAN, RECEIVERS

    assert tuple(r.value for r in cli.ReceiverName) == RECEIVERS
    assert DEFAULT_RECEIVER == "differential" and DEFAULT_SPAN == 3
