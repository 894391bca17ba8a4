"""``motionsig detect`` with the model options: the Monte Carlo and the calibration take the vehicle's
settings (their defaults reproduce the plain command byte for byte), a record takes the filters' settings,
the carrier search reports the estimated carrier, and every refusal names its option."""

import pytest

from tests.cli.helpers import one_line_error, run, table

MC = ("detect", "--montecarlo", "--method", "fft", "--trials", "3", "--fr-list", "0.01", "--R-list", "1e-3",
      "--horizons", "10", "--workers", "1", "-q")  # fmt: skip
DEFAULTS = ("--T", "0.05", "--mrho", "20", "--a-r", "10", "--a-sig", "0.5", "--sigma-a", "0.01", "--fc", "1",
            "--q-model", "per-step", "--feedback", "true", "--f-d", "0", "--pole-wn", "12.566370614359172")  # fmt: skip


def _record(capsys, tmp_path, *args: str) -> str:
    path = tmp_path / "rec.csv"
    rc, _, err = run(capsys, "simulate", "-o", str(path), "-q", *args)
    assert rc == 0, err
    return str(path)


@pytest.mark.parametrize("mode", ["--montecarlo", "--calibrate"])
def test_explicit_defaults_reproduce_the_plain_run(capsys, mode):
    """Every new option at its default gives the plain command's output, byte for byte."""
    base = (mode, *MC[2:]) if mode == "--montecarlo" else ("--calibrate", *MC[2:], "--null-trials", "20")
    rc, plain, _ = run(capsys, "detect", *base)
    rc2, explicit, _ = run(capsys, "detect", *base, *DEFAULTS)
    assert rc == rc2 == 0 and plain == explicit


def test_montecarlo_takes_the_vehicle_and_filter_options(capsys, tmp_path):
    rc, out, err = run(
        capsys, *MC, "--T", "0.1", "--mrho", "10", "--a-r", "1", "--sigma-a", "0.02", "--K", "60,14",
        "--Ar", "known", "--q-model", "continuous", "--feedback", "estimate", "--f-d", "0.01",
        "--fd-grid", "-0.02:0.02:5", "--Q0", "1e-6,1e-3,0,0",
    )  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path)
    m = t.meta
    assert (m["T"], m["m_rho"], m["a_r"], m["sigma_a"], m["K"]) == (0.1, 10, 1.0, 0.02, [60.0, 14.0])
    assert (m["A_r"], m["q_model"], m["feedback"], m["f_d"]) == ("known", "continuous", "estimate", 0.01)
    assert m["fc_grid"] == pytest.approx([0.98, 0.99, 1.0, 1.01, 1.02]) and "pct_fc_correct" in t.columns


def test_record_carrier_search_reports_the_carrier(capsys, tmp_path):
    """simulate --f-d 0.02 | detect --fd-grid …: fc_hat is the true carrier 1.02 Hz with a matched model."""
    src = _record(capsys, tmp_path, "--f-d", "0.02", "--R", "1e-3", "--duration", "40", "--mode", "3")
    rc, out, err = run(
        capsys, "detect", src, "--fd-grid", "-0.04,-0.02,0,0.02,0.04", "--Ar", "known", "--Q0", "1e-6,1e-4,0,0",
        "--Qa", "0", "--c-r", "1", "--method", "fft", "--horizons", "40",
    )  # fmt: skip
    assert rc == 0, err
    t = table(out, tmp_path, "det.csv")
    row = dict(zip(t.columns, t.rows[0], strict=True))
    assert float(row["fc_hat"]) == pytest.approx(1.02) and row["correct"] == "true"
    assert t.meta["known_reference"]["a_r"] == 10.0 and t.meta["input_meta"]["f_d"] == 0.02


def test_known_reference_needs_a_stated_reference(capsys, tmp_path):
    """A user's export without a_r, f_r: --Ar known is refused (naming --Ar) unless --a-r and --f-r say it."""
    path = tmp_path / "export.csv"
    path.write_text("time,y\n" + "".join(f"{k * 0.05:.2f},{0.01 * k}\n" for k in range(400)))
    err = one_line_error(capsys, "detect", str(path), "--Ar", "known", "--horizons", "10")
    assert "--Ar" in err and "--a-r" in err
    rc, _, err = run(
        capsys, "detect", str(path), "--Ar", "known", "--a-r", "10", "--f-r", "0.01", "--horizons", "10"
    )
    assert rc == 0, err


@pytest.mark.parametrize(
    ("args", "option"),
    [
        ((*MC, "--R", "1e-3"), "--R"),
        ((*MC, "--f-r", "0.1"), "--f-r"),
        ((*MC, "--q-model", "continuous", "--K", "0,50"), "--q-model"),
        ((*MC, "--fd-grid", "-0.1:0.1:3", "--fc-grid", "1"), "--fd-grid"),
        ((*MC, "--fd-grid", "a:b:c"), "--fd-grid"),
        ((*MC, "--fd-grid", "0.1:-0.1:3"), "--fd-grid"),
        ((*MC, "--f-d", "-3"), "--f-d"),
        ((*MC, "--feedback", "observer"), "--feedback"),
        ((*MC, "--T", "-1"), "--T"),
        (("detect", "--montecarlo", "--example", "2d", "--T", "0.1"), "--T"),
    ],
)
def test_montecarlo_refusals_name_the_option(capsys, args, option):
    assert option in one_line_error(capsys, *args)


def test_record_refusals_name_the_option(capsys, tmp_path):
    src = _record(capsys, tmp_path, "--duration", "10")
    assert "--f-d" in one_line_error(capsys, "detect", src, "--f-d", "0.1")
    radar = tmp_path / "radar.csv"
    rc, _, _ = run(capsys, "simulate", "--example", "2d", "--duration", "5", "-o", str(radar), "-q")
    assert rc == 0
    assert "--q-model" in one_line_error(capsys, "detect", str(radar), "--q-model", "continuous")
    assert "--feedback" in one_line_error(capsys, "detect", str(radar), "--feedback", "estimate")


def test_record_feedback_option_sets_the_null_records_loop(capsys, tmp_path):
    """--feedback on a record describes the true loop of the --pfa null records: listed as an option."""
    src = _record(capsys, tmp_path, "--duration", "10", "--R", "1e-3")
    args = ("detect", src, "--method", "fft", "--pfa", "0.2", "--null-trials", "10", "--workers", "1")
    rc, out, err = run(capsys, *args, "--feedback", "estimate")
    assert rc == 0, err
    meta = table(out, tmp_path, "d.csv").meta
    assert meta["model"]["feedback"] == "estimate" and meta["model_sources"]["feedback"].startswith("option")
    rc, plain, _ = run(capsys, *args)
    assert plain != out


def test_preset_paper_is_its_q0_and_qa_and_explicit_options_win(capsys, tmp_path):
    """--preset paper = --Q0 1e-3,1e-2,0.1,0.1 --Qa 100 (c_r 100) byte for byte (the reading in
    data/lmp_search.csv); a given --Qa wins over the preset's; the 2d example refuses it, naming --preset."""
    args = ("detect", "--montecarlo", "--trials", "2", "--fr-list", "0.01", "--R-list", "1e-1", "--horizons",
            "40", "--workers", "1", "-q")  # fmt: skip
    rc, preset, err = run(capsys, *args, "--preset", "paper")
    rc2, explicit, _ = run(capsys, *args, "--c-r", "100", "--Q0", "1e-3,1e-2,0.1,0.1", "--Qa", "100")
    assert rc == rc2 == 0 and preset == explicit, err
    rc, plain, _ = run(capsys, *args)
    m = table(plain, tmp_path).meta
    assert plain != preset and (m["c_r"], m["Q_a"]) == (100.0, 1.0)
    rc, mixed, _ = run(capsys, *args, "--preset", "paper", "--Qa", "3")
    m = table(mixed, tmp_path, "mixed.csv").meta
    assert m["Q_a"] == 3.0 and m["Q0"] == [1e-3, 1e-2, 0.1, 0.1]
    err = one_line_error(capsys, "detect", "--montecarlo", "--example", "2d", "--preset", "paper")
    assert "--preset" in err
