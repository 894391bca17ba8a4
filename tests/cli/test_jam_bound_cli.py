"""`motionsig jam-bound`: tables against the printed values, curves, conventions, bad input."""

import json
import math
import re
import subprocess
import sys

import numpy as np
import pytest

from motionsig_cli.tables import read_table
from tests.cli.helpers import run, table


def test_table_2_1_cli(capsys, tmp_path):
    rc, out, err = run(capsys, "jam-bound", "table")
    assert rc == 0 and "6/6 rows agree" in err
    t = table(out, tmp_path)
    assert t.meta["which"] == "2.1" and t.meta["convention"] == "corrected"
    status = dict(zip(zip(t.column("K"), t.column("P_DL"), strict=True), t.column("status"), strict=True))
    assert status[("1000", "0.98")] == "unattainable-as-printed"
    dev = np.array([float(v or "nan") for v in t.column("deviation_db")])
    tol = np.array([float(v or "nan") for v in t.column("tolerance_db")])
    ok = ~np.isnan(dev)
    assert ok.sum() == 5 and np.all(np.abs(dev[ok]) <= tol[ok])
    assert "> 130" in t.column("printed_erp_dbw")


def test_table_1_1_cli_flags(capsys, tmp_path):
    rc, out, _ = run(capsys, "jam-bound", "table", "--which", "1.1", "-q")
    assert rc == 0
    t = table(out, tmp_path)
    flags = dict(zip(t.column("K"), t.column("flags"), strict=True))
    assert "beamwidth 15" in flags["1"]
    assert "Table 2.1 prints 56 dBW for P_DL 0.88, 51 dBW for P_DL 0.999, not 53" in flags["100"]
    assert abs(t.meta["text_anchor_k1"]["beamwidth_deg"] - 20) < 1


def test_curves_figure_preset_and_plot(capsys, tmp_path):
    out_csv, fig = tmp_path / "f.csv", tmp_path / "f.svg"
    rc, _, _ = run(
        capsys, "jam-bound", "curves", "--figure", "2.4", "-o", str(out_csv), "--plot", str(fig), "-q"
    )
    assert rc == 0 and fig.stat().st_size > 0
    t = read_table(out_csv)
    assert set(t.column("quantity")) == {"nadl"} and set(t.column("K")) == {"10"}
    assert sorted(set(t.numeric("t"))) == [0.0, 0.1, 0.2, 0.3, 0.5]
    lv = t.numeric("log10_value")
    assert np.all(np.isfinite(lv)) and lv.min() < -300  # exact logs where the value underflows
    empty = [v == "" for v in t.column("value")]
    assert any(empty) and all(e == (x < -690 / math.log(10)) for e, x in zip(empty, lv, strict=True))


def test_report_convention_shifts_nfl_by_3_db(capsys, tmp_path):
    args = ["jam-bound", "curves", "--K", "100", "--pdl", "0.88", "--t", "0", "--quantity", "nfl", "-q"]
    _, a, _ = run(capsys, *args, "--x-min", "-20", "--x-max", "-10", "--step", "0.5")
    shift = 10 * math.log10(2)
    _, b, _ = run(
        capsys,
        *args,
        "--x-min",
        str(-20 - shift),
        "--x-max",
        str(-10 - shift),
        "--step",
        "0.5",
        "--convention",
        "report",
    )
    ta, tb = table(a, tmp_path, "a.csv"), table(b, tmp_path, "b.csv")
    assert tb.meta["convention"] == "report"
    # x is rounded to 11 decimals: 5e-12 dB × slope (< 25 decades/dB here) < 1e-9 relative
    np.testing.assert_allclose(ta.numeric("log10_value"), tb.numeric("log10_value"), rtol=1e-9)


def test_threshold_and_design_cli(capsys, tmp_path):
    rc, out, _ = run(
        capsys, "jam-bound", "threshold", "--K", "1000", "--pdl", "0.98,0.999", "-f", "json", "-q"
    )
    assert rc == 0
    doc = json.loads(out)
    rows = {r["P_DL"]: r for r in doc["data"]}
    assert rows[0.98]["attainable"] is False and rows[0.98]["erp_dbw"] is None
    assert rows[0.999]["ill_conditioned"] is True and abs(rows[0.999]["erp_dbw"] - 75.73) < 0.01
    rc, out, _ = run(capsys, "jam-bound", "design", "--K", "10", "--pd", "0.9", "--t", "0.1", "-q")
    t = table(out, tmp_path)
    assert abs(t.numeric("P_DL")[0] - 0.9988605978) < 1e-9 and t.column("solved") == ["P_DL"]


def test_same_file_for_out_and_plot_is_refused(capsys, tmp_path):
    target = tmp_path / "same.png"
    rc, _, err = run(capsys, "jam-bound", "curves", "-o", str(target), "--plot", str(target))
    assert rc == 2 and "--plot" in err and not target.exists()


def test_figure_name_is_normalised(capsys, tmp_path):
    rc, out, _ = run(capsys, "jam-bound", "curves", "--figure", "Fig. 2.04", "--step", "1", "-q")
    t = table(out, tmp_path)
    assert rc == 0 and t.meta["figure"] == "2.4" and set(t.column("figure")) == {"2.4"}


def test_level_at_the_supremum_is_unattainable_not_a_crash(capsys, tmp_path):
    rc, out, _ = run(
        capsys, "jam-bound", "threshold", "--K", "1000", "--pdl", "0.999", "--level", "0.02021399050431", "-q"
    )
    assert rc == 0 and table(out, tmp_path).column("attainable") == ["false"]


def test_antenna_cli(capsys, tmp_path):
    rc, out, _ = run(capsys, "jam-bound", "antenna", "--erp-dbw", "33", "--rf-w", "30", "-q")
    assert rc == 0 and abs(table(out, tmp_path).numeric("beamwidth_deg")[0] - 20.0) < 0.01


def test_speed_of_light_default_is_the_core_constant():
    from motionsig_cli.cli import jam_bound
    from motionsig_cli.surveillance import jamming

    assert jam_bound.C_MPH == jamming.C_MPH


def _modules_after(code: str) -> set[str]:
    probe = code + "\nimport sys\nprint(' '.join(sorted(sys.modules)))\n"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return set(out.stdout.split())


def test_cli_module_imports_no_numerical_library():
    loaded = _modules_after("import motionsig_cli.cli.jam_bound")
    assert not loaded & {"numpy", "scipy", "matplotlib", "motionsig_cli.atc10.jamming"}


@pytest.mark.parametrize(
    ("args", "absent"),
    [
        (["table", "-q"], {"matplotlib", "scipy.stats"}),
        (["design", "--K", "10", "--pdl", "0.9", "-q"], {"matplotlib", "scipy.stats", "scipy.optimize"}),
        (["curves", "--K", "10", "--t", "0", "--step", "1", "-q"], {"matplotlib", "scipy.optimize"}),
    ],
)
def test_commands_import_only_what_they_use(args, absent):
    code = (
        "import contextlib, io\nfrom motionsig_cli.cli.app import main\n"
        f"with contextlib.redirect_stdout(io.StringIO()):\n    assert main({['jam-bound', *args]!r}) == 0"
    )
    assert not _modules_after(code) & absent


@pytest.mark.parametrize("name", ["curves", "threshold", "table", "design", "antenna"])
def test_help_cites_no_internal_document(capsys, name):
    rc, out, _ = run(capsys, "jam-bound", name, "--help")
    assert rc == 0 and "Usage" in out
    assert not re.search(r"\bspec\b|issue \d|seed 00\d", out, flags=re.IGNORECASE), out
