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
    ],
)
def test_bad_input(capsys, args, needle):
    rc, _, err = run(capsys, "slrt", *args)
    assert rc == 2 and err.count("\n") == 1 and needle in err and "Traceback" not in err
