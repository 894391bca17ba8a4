"""`motionsig slrt` (issue 10): outputs, figures, reproducibility and bad input."""

import numpy as np
import pytest

from tests.cli.helpers import run, table


def test_curves_and_plots(capsys, tmp_path):
    png, scan = tmp_path / "s.png", tmp_path / "scan.png"
    rc, out, err = run(
        capsys, "slrt", "--runs", "8", "--scans", "10", "--plot", str(png), "--plot-scan", str(scan)
    )
    assert rc == 0 and png.stat().st_size > 20_000 and scan.stat().st_size > 10_000
    t = table(out, tmp_path)
    assert set(t.column("method")) == {"ckf", "dkf", "lkf"}
    assert len(t.rows) == 4 * 3 * 10
    assert t.meta["sprt"]["log_B"] == pytest.approx(6.802, abs=1e-3)
    mean = t.numeric("mean_loglr")
    case = t.column("case")
    assert all(m < 0 for m, c in zip(mean, case, strict=True) if c == "no target")
    assert "mean log LR at scan 10" in err


def test_decisions_view_and_seed(capsys, tmp_path):
    args = ("slrt", "--view", "decisions", "--runs", "10", "--scans", "8", "--pd", "0.9", "--seed", "3", "-q")
    rc, out1, _ = run(capsys, *args)
    _, out2, _ = run(capsys, *args)
    assert rc == 0 and out1 == out2
    t = table(out1, tmp_path)
    frac = t.numeric("confirmed") + t.numeric("deleted") + t.numeric("undecided")
    np.testing.assert_allclose(frac, 1.0)
    assert set(t.column("case")) == {"target, p_D = 0.9", "no target"}


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--pd", "0"), "--pd"),
        (("--pd", "1.5"), "--pd"),
        (("--filter-pd", "0"), "--filter-pd"),
        (("--clutter", "-1"), "--clutter"),
        (("--alpha", "0.5"), "--alpha"),
        (("--beta", "0"), "--beta"),
        (("--sensors", "0"), "--sensors"),
        (("--radius", "0"), "--radius"),
        (("--sigma-r", "0"), "--sigma-r"),
        (("--sigma-phi-deg", "-1"), "--sigma-phi-deg"),
        (("--methods", "ukf"), "--methods"),
        (("--runs", "100000", "--scans", "1000"), "--runs"),
        (("--pd", "1", "--target-only"), "--pd"),
        (("--runs", "1", "--scans", "100000"), "--runs"),
        (("--radius", "30000"), "--radius"),
        (("--sensors", "3", "--radius", "1e-200"), "--radius"),
        (("--sigma-r", "1e-170"), "--sigma-r"),
        (("--T", "1e300"), "--T"),
        (("--q", "inf"), "--q"),
        (("--plot-scan", "same.png", "-o", "same.png"), "--plot-scan"),
        (("--plot", "b.png", "--plot-scan", "b.png"), "--plot-scan"),
        (("--plot-scan", "x.xyz"), "--plot-scan"),
    ],
)
def test_bad_input(capsys, args, needle):
    rc, _, err = run(capsys, "slrt", *args)
    assert rc == 2 and err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_stop_freezes_scores_and_pd_one_gives_minus_inf_not_nan(capsys, tmp_path):
    rc, out, _ = run(capsys, "slrt", "--stop", "--runs", "6", "--scans", "6", "--pd", "0.9", "-q")
    t = table(out, tmp_path)
    assert rc == 0 and t.meta["stop"] is True
    sel = [i for i, (c, m) in enumerate(zip(t.column("case"), t.column("method"), strict=True))
           if c == "target, p_D = 0.9" and m == "ckf"]  # fmt: skip
    mean = t.numeric("mean_loglr")[sel]
    assert np.all(mean == mean[0])  # every run decided at scan 1 and frozen there
    # p_D = 1 and a sensor that sees nothing: the target hypothesis is impossible, log LR = -inf (never NaN)
    rc, out, _ = run(capsys, "slrt", "--filter-pd", "1", "--clutter", "0", "--pd", "0.9", "--runs", "3",
                     "--scans", "4", "--methods", "ckf", "-q")  # fmt: skip
    t = table(out, tmp_path, "b.csv")
    nt = [v for v, c in zip(t.column("mean_loglr"), t.column("case"), strict=True) if c == "no target"]
    assert rc == 0 and set(nt) == {"-inf"} and "clutter_floor" in t.meta
